#!/usr/bin/env python3
"""A vertex of very high degree (a hub) as .pfc: one vertex with N spokes.

    python3 bench/gen_hub.py N OUT.pfc [--flaw]

The spokes go from (0, 0) to N distinct lattice points about 10^7 units
away, evenly around it: a valid map whose every segment meets the hub's
cell of any grid. --flaw adds one short spoke along the first one's first
units, which overlaps it there: an invalid map whose only conflict is at
the hub. Deterministic.
"""
import math
import sys


def main():
    args = [a for a in sys.argv[1:] if a != "--flaw"]
    flaw = len(args) < len(sys.argv) - 1
    n, out = int(float(args[0])), args[1]
    radius = 10 ** 7
    seen, far = set(), []
    for i in range(n):
        a = 2 * math.pi * i / n
        p = (round(radius * math.cos(a)), round(radius * math.sin(a)))
        if p not in seen:
            seen.add(p)
            far.append(p)
    with open(out, "w") as f:
        f.write("pfc 1\nv 0 0\n")
        for p in far:
            f.write("v %d %d\n" % p)
        if flaw:  # far[0] is (radius, 0): a spoke to (1, 0) lies along it
            f.write("v 1 0\n")
        for i in range(len(far)):
            f.write("e 0 %d\n" % (i + 1))
        if flaw:
            f.write("e 0 %d\n" % (len(far) + 1))
    sys.stderr.write("%s: a hub of %d spokes%s\n" % (out, len(far) + flaw, ", one overlapping" if flaw else ""))


if __name__ == "__main__":
    main()
