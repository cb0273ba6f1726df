#!/usr/bin/env python3
"""A synthetic continental polygon coverage in longitude/latitude, for the
GIS packing benchmark (bench/run-gis.sh).

    gen_continent.py OUT.geojson [COLS ROWS POINTS_PER_SIDE [SEED [W S E N]]]

Defaults: 80 x 50 county-like cells over 125-67 W, 25-49 N (the extent of the
conterminous United States), 250 shape points inside every side: about 4
million shape points, 130 MB of GeoJSON. W S E N: another extent (degrees).

- Cells are the faces of a jittered grid. Each side between two grid nodes is
  one jagged polyline (a bounded random walk across the side, tapered to
  zero at its ends so that the sides meeting at a node stay in disjoint
  cones), computed once and written into both neighbours, forwards into one
  and backwards into the other: shared borders are bit-identical, as in a
  real topologically built layer.
- One cell in 20 has a lake: a jagged ring around its middle that is a hole
  of the cell and, bit-identically, a feature of its own.
- One cell in 50 along the coasts (the grid's rim) gets an offshore island
  in a MultiPolygon with the cell.
Every feature has `id` and `name`. Coordinates are printed with 9 decimals
(about 0.1 mm), short of a double's digits as real data is.
"""
import json
import math
import random
import sys

LON0, LON1, LAT0, LAT1 = -125.0, -67.0, 25.0, 49.0


def walk(rng, n):
    """n values in [-1, 1]: a reflected random walk, jagged at every step."""
    v, out = 0.0, []
    for _ in range(n):
        v += rng.uniform(-0.35, 0.35)
        if v > 1:
            v = 2 - v
        if v < -1:
            v = -2 - v
        out.append(v)
    return out


def side(rng, a, b, k, amp):
    """The k interior points of the jagged side from node a to node b."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    nx, ny = -dy, dx  # the normal, as long as the side
    w = walk(rng, k)
    pts = []
    for i in range(k):
        t = (i + 1) / (k + 1)
        s = amp * math.sin(math.pi * t) * w[i]
        pts.append((a[0] + t * dx + s * nx, a[1] + t * dy + s * ny))
    return pts


def ring_around(rng, cx, cy, rx, ry, n):
    """A jagged closed ring around (cx, cy) within the ellipse (rx, ry)."""
    w = walk(rng, n)
    pts = []
    for i in range(n):
        a = 2 * math.pi * i / n
        r = 0.75 + 0.2 * w[i]
        pts.append((cx + rx * r * math.cos(a), cy + ry * r * math.sin(a)))
    return pts + [pts[0]]


def fmt(p):
    return [round(p[0], 9), round(p[1], 9)]


def main():
    out = sys.argv[1]
    cols = int(sys.argv[2]) if len(sys.argv) > 2 else 80
    rows = int(sys.argv[3]) if len(sys.argv) > 3 else 50
    k = int(sys.argv[4]) if len(sys.argv) > 4 else 250
    rng = random.Random(int(sys.argv[5]) if len(sys.argv) > 5 else 1)
    lon0, lat0, lon1, lat1 = ([float(v) for v in sys.argv[6:10]] if len(sys.argv) > 9 else
                              (LON0, LAT0, LON1, LAT1))
    cw, ch = (lon1 - lon0) / cols, (lat1 - lat0) / rows
    node = {}
    for j in range(rows + 1):
        for i in range(cols + 1):
            jit = 0 if i in (0, cols) or j in (0, rows) else 0.15
            node[i, j] = (lon0 + (i + rng.uniform(-jit, jit)) * cw,
                          lat0 + (j + rng.uniform(-jit, jit)) * ch)
    # sides, rounded once so that both users print the same digits
    horiz = {(i, j): [fmt(p) for p in side(rng, node[i, j], node[i + 1, j], k, 0.12)]
             for j in range(rows + 1) for i in range(cols)}
    vert = {(i, j): [fmt(p) for p in side(rng, node[i, j], node[i, j + 1], k, 0.12)]
            for j in range(rows) for i in range(cols + 1)}
    fnode = {key: fmt(p) for key, p in node.items()}
    points = 0
    with open(out, "w") as f:
        f.write('{"type":"FeatureCollection","name":"continent","features":[\n')
        first = True

        def feature(fid, name, geom):
            nonlocal first, points
            f.write(("" if first else ",\n") + json.dumps(
                {"type": "Feature", "properties": {"id": fid, "name": name}, "geometry": geom},
                separators=(",", ":")))
            first = False

        fid = 0
        for j in range(rows):
            for i in range(cols):
                # counter-clockwise: bottom, right, top (backwards), left (backwards)
                shell = ([fnode[i, j]] + horiz[i, j] + [fnode[i + 1, j]] + vert[i + 1, j] +
                         [fnode[i + 1, j + 1]] + horiz[i, j + 1][::-1] + [fnode[i, j + 1]] +
                         vert[i, j][::-1] + [fnode[i, j]])
                polys = [[shell]]
                cx = (node[i, j][0] + node[i + 1, j + 1][0]) / 2
                cy = (node[i, j][1] + node[i + 1, j + 1][1]) / 2
                if rng.random() < 0.05:
                    lake = [fmt(p) for p in ring_around(rng, cx, cy, 0.12 * cw, 0.12 * ch, 4 * k)]
                    polys[0].append(lake[::-1])
                    feature(fid, f"lake {fid}", {"type": "Polygon", "coordinates": [lake]})
                    points += len(lake)
                    fid += 1
                rim = i in (0, cols - 1) or j in (0, rows - 1)
                if rim and rng.random() < 0.2:
                    ox = cx + (-cw if i == 0 else cw if i == cols - 1 else 0)
                    oy = cy + (-ch if j == 0 else ch if j == rows - 1 else 0)
                    polys.append([[fmt(p) for p in ring_around(rng, ox, oy, 0.3 * cw,
                                                                0.3 * ch, 2 * k)]])
                points += sum(len(r) for p in polys for r in p)
                geom = ({"type": "Polygon", "coordinates": polys[0]} if len(polys) == 1 else
                        {"type": "MultiPolygon", "coordinates": polys})
                feature(fid, f"county {j}-{i}", geom)
                fid += 1
        f.write("\n]}\n")
    print(f"{out}: {fid} features, {points} shape points", file=sys.stderr)


main()
