#!/usr/bin/env python3
"""Nested polygons and their naive point-in-polygon oracle, for
tests/cli/gis_link.sh.

    link_oracle.py make OUT.geojson SEED KIND
        KIND nested: a coast (a shell with lakes, islands in the lakes, lakes
                     in those islands: one feature, rings nested four deep),
                     an archipelago of islands inside the coast's box but
                     outside it, a second feature covering some islands and
                     a lake (overlapping features, sharing no border), a
                     feature with a hole holding another feature, a line
                     inside the coast; no two rings meet, so nothing is
                     re-noded and every face is linked by the topology
        KIND crossing: the same with rings of different features crossing
                     (re-noded: some faces anchored by witness points)
    link_oracle.py points DATASET SEED N POINTS_OUT EXPECTED_OUT
        N random points in the data's box, at least MARGIN from every ring,
        as "x,y" lines, and per point the fids (positions in the layer) of
        the polygon features whose rings hold it an odd number of times
        (even-odd rule, a plain ray walk over every ring).

Coordinates are metres of a projected CRS (UTM 31N), kept as they are, so
the oracle works in the file's own coordinates.
"""
import json
import math
import random
import sys

MARGIN = 0.6  # lattice units are 1e-? of these; points stay clear of rings


def square(cx, cy, r, ccw=True):
    pts = [(cx - r, cy - r), (cx + r, cy - r), (cx + r, cy + r), (cx - r, cy + r)]
    if not ccw:
        pts.reverse()
    return [list(p) for p in pts + [pts[0]]]


def polygon_ring(cx, cy, r, n, rng):
    """A star-shaped ring of n points around (cx, cy), radius ~r."""
    pts = []
    for k in range(n):
        a = 2 * math.pi * k / n
        rr = r * (0.8 + 0.2 * rng.random())
        pts.append([round(cx + rr * math.cos(a), 3), round(cy + rr * math.sin(a), 3)])
    return pts + [pts[0]]


def make(path, seed, kind):
    rng = random.Random(seed)
    feats = []
    # the coast: rings nested four deep, as one MultiPolygon
    coast = [[polygon_ring(0, 0, 400, 400, rng),
              polygon_ring(-150, 0, 100, 60, rng),       # a lake
              polygon_ring(150, 0, 100, 60, rng)],       # another lake
             [polygon_ring(-150, 0, 60, 40, rng),        # an island in the lake
              polygon_ring(-150, 0, 20, 20, rng)],       # a lake in that island
             [polygon_ring(-150, 0, 10, 12, rng)]]       # an island in that lake
    feats.append({"type": "MultiPolygon", "coordinates": coast})
    # an archipelago inside the coast's box, outside the coast
    islands = []
    for t in range(-440, 441, 20):
        for cx, cy in ((t, 460), (t, -460), (460, t), (-460, t)):
            islands.append([square(cx, cy, 4)])
    feats.append({"type": "MultiPolygon", "coordinates": islands})
    # overlapping features sharing no border: a big square around the second
    # lake and a few islands of the archipelago
    feats.append({"type": "Polygon", "coordinates": [square(150, 0, 130)]})
    # a feature with a hole holding another feature (and a line feature)
    feats.append({"type": "Polygon", "coordinates": [square(0, 250, 60), square(0, 250, 30, False)]})
    feats.append({"type": "Polygon", "coordinates": [square(0, 250, 10)]})
    feats.append({"type": "LineString", "coordinates": [[-50, -200], [0, -180], [60, -210]]})
    if kind == "crossing":
        # rings of different features crossing: re-noded
        feats.append({"type": "Polygon", "coordinates": [square(-60, 100, 80)]})
        feats.append({"type": "Polygon", "coordinates": [square(-20, 140, 70)]})
    out = {"type": "FeatureCollection",
           "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32631"}},
           "features": [{"type": "Feature", "properties": {"name": f"f{i}", "rank": i * 10 + 1,
                                                           "share": i / 8},
                         "geometry": g} for i, g in enumerate(feats)]}
    with open(path, "w") as f:
        json.dump(out, f)


def rings_of(geom):
    t = geom["type"]
    if t == "Polygon":
        return geom["coordinates"]
    if t == "MultiPolygon":
        return [r for p in geom["coordinates"] for r in p]
    return []


def holds(ring, x, y):
    inside = False
    for (xi, yi), (xj, yj) in zip(ring, ring[1:] + ring[:1]):
        if (yi > y) != (yj > y) and x < xi + (xj - xi) * (y - yi) / (yj - yi):
            inside = not inside
    return inside


def seg_dist(px, py, ax, ay, bx, by):
    dx, dy = bx - ax, by - ay
    t = 0 if dx == dy == 0 else max(0, min(1, ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy)))
    return math.hypot(px - ax - t * dx, py - ay - t * dy)


def points(path, seed, n, points_out, expected_out):
    feats = json.load(open(path))["features"]
    rings = [(fid, r) for fid, f in enumerate(feats) for r in rings_of(f["geometry"])]
    segs = [(r[k], r[k + 1]) for _, r in rings for k in range(len(r) - 1)]
    xs = [p[0] for _, r in rings for p in r]
    ys = [p[1] for _, r in rings for p in r]
    rng = random.Random(seed)
    pts, expected = [], []
    while len(pts) < n:
        x, y = rng.uniform(min(xs), max(xs)), rng.uniform(min(ys), max(ys))
        if any(seg_dist(x, y, a[0], a[1], b[0], b[1]) < MARGIN for a, b in segs):
            continue
        odd = {}
        for fid, r in rings:
            odd[fid] = odd.get(fid, False) ^ holds(r, x, y)
        pts.append(f"{x:.6f},{y:.6f}")
        expected.append(sorted(fid for fid, o in odd.items() if o))
    open(points_out, "w").write("\n".join(pts) + "\n")
    json.dump(expected, open(expected_out, "w"))


if __name__ == "__main__":
    if sys.argv[1] == "make":
        make(sys.argv[2], int(sys.argv[3]), sys.argv[4])
    else:
        points(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5], sys.argv[6])
