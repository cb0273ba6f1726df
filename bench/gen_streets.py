#!/usr/bin/env python3
"""A street-network-like planar map as .pfc, of about N shape points.

    python3 bench/gen_streets.py N OUT.pfc [SEED] [--stray]

Junctions on a jittered square grid (spacing 1000 lattice units, each
junction moved by up to 200 in x and y), streets between 4-neighbours as
curved polylines (a half sine wave of amplitude up to 60 across the
street, zero at both ends, so streets meeting at a junction leave it apart
and never cross), 8 to 16 shape points a street; 12 % of the streets
dropped where both ends keep another street, which leaves junctions of
degree 1 (dead ends) to 4.
Integer coordinates: the map is exact as written. Deterministic for a
seed. The kind of map issue 32 asks to pack through partitions.
--stray adds one short street at (4e8, 4e8), far from the others (a stray
feature, as one at null island in a city's layer): the network, 2*10^5
to 2*10^6 units wide, is left in a corner of a box some thousand times
larger.
"""
import math
import random
import sys


def main():
    args = [a for a in sys.argv[1:] if a != "--stray"]
    stray = len(args) < len(sys.argv) - 1
    target = int(float(args[0]))
    out = args[1]
    rng = random.Random(int(args[2]) if len(args) > 2 else 32)
    per_street = 11  # points a street: 12 interior, less the 12 % dropped
    side = max(2, int(math.sqrt(target / (2 * per_street))))
    spacing = 1000
    jx = [[rng.randint(-200, 200) for _ in range(side)] for _ in range(side)]
    jy = [[rng.randint(-200, 200) for _ in range(side)] for _ in range(side)]
    streets = []
    degree = [[0] * side for _ in range(side)]
    for j in range(side):
        for i in range(side):
            for di, dj in ((1, 0), (0, 1)):
                if i + di < side and j + dj < side:
                    streets.append((i, j, i + di, j + dj))
                    degree[j][i] += 1
                    degree[j + dj][i + di] += 1
    kept = []
    for (i, j, k, l) in streets:
        # never leave a junction without a street (an isolated vertex)
        drop = rng.random() < 0.12 and degree[j][i] > 1 and degree[l][k] > 1
        if drop:
            degree[j][i] -= 1
            degree[l][k] -= 1
        else:
            kept.append((i, j, k, l))
    with open(out, "w") as f:
        f.write("pfc 1\n")
        for j in range(side):
            for i in range(side):
                f.write("v %d %d\n" % (i * spacing + jx[j][i], j * spacing + jy[j][i]))
        if stray:
            f.write("v 400000000 400000000\nv 400000010 400000000\n")
        points = side * side
        for (i, j, k, l) in kept:
            ax, ay = i * spacing + jx[j][i], j * spacing + jy[j][i]
            bx, by = k * spacing + jx[l][k], l * spacing + jy[l][k]
            n = rng.randint(8, 16)
            amp = rng.uniform(-60, 60)
            dx, dy = bx - ax, by - ay
            length = math.hypot(dx, dy)
            px, py = -dy / length, dx / length
            xy = []
            last = None
            for s in range(1, n + 1):
                t = s / (n + 1)
                off = amp * math.sin(math.pi * t)
                p = (round(ax + dx * t + px * off), round(ay + dy * t + py * off))
                if p != last and p != (ax, ay) and p != (bx, by):
                    xy.append("%d %d" % p)
                    last = p
            points += len(xy)
            f.write("e %d %d %s\n" % (j * side + i, l * side + k, " ".join(xy)))
        if stray:
            f.write("e %d %d\n" % (side * side, side * side + 1))
    sys.stderr.write("%s: %d junctions, %d streets, %d points\n" % (out, side * side, len(kept), points))


if __name__ == "__main__":
    main()
