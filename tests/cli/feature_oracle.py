#!/usr/bin/env python3
"""Independent point-in-feature oracle for tests/cli/gis_features.sh.

    feature_oracle.py DATASET KEY SEED N POINTS_OUT EXPECTED_OUT

Draws N random points (seeded), each in the envelope of a random polygon
feature (so that most fall in some feature), keeps those at
least MARGIN from every polygon boundary, and writes them as "x,y" lines to
POINTS_OUT and, for each, the polygon features that contain it (fid, KEY
value), computed by GDAL/OGR with GEOS, to EXPECTED_OUT (JSON). Points near
borders are left out: there the lattice snapping of hpfc-pack may decide
differently from the source's floating-point geometry, and the test is
about attribution, not about sub-lattice geometry. Features whose rings cross
the antimeridian (their envelope spans over 180 degrees of longitude) mean
something else in the plane than on the sphere, so no point is drawn inside
their envelopes: hpfc-pack cuts them, GEOS here would not.
"""
import json
import random
import sys

from osgeo import ogr

MARGIN = 0.02  # degrees: ~2 km, thousands of lattice units


def main():
    path, key, seed, n, points_out, expected_out = sys.argv[1:7]
    ogr.UseExceptions()
    ds = ogr.Open(path)
    layer = ds.GetLayer(0)
    feats = []
    for f in layer:
        g = f.GetGeometryRef()
        if g is None or g.IsEmpty():
            continue
        if ogr.GT_Flatten(g.GetGeometryType()) not in (ogr.wkbPolygon, ogr.wkbMultiPolygon):
            continue
        feats.append((f.GetFID(), f.GetField(key), g.Clone(), g.GetBoundary()))
    wrapping = [g.GetEnvelope() for _, _, g, _ in feats
                if g.GetEnvelope()[1] - g.GetEnvelope()[0] > 180]
    plain = [f for f in feats if f[2].GetEnvelope()[1] - f[2].GetEnvelope()[0] <= 180]
    rng = random.Random(int(seed))
    points, expected = [], []
    while len(points) < int(n):
        xmin, xmax, ymin, ymax = rng.choice(plain)[2].GetEnvelope()
        x, y = rng.uniform(xmin, xmax), rng.uniform(ymin, ymax)
        if any(e[2] <= y <= e[3] for e in wrapping):
            continue
        p = ogr.Geometry(ogr.wkbPoint)
        p.AddPoint_2D(x, y)
        if any(b.Distance(p) < MARGIN for _, _, _, b in feats):
            continue
        inside = [{"fid": fid, "key": k} for fid, k, g, _ in feats if g.Contains(p)]
        points.append(f"{x:.6f},{y:.6f}")
        expected.append(sorted(inside, key=lambda d: d["fid"]))
    with open(points_out, "w") as out:
        out.write("\n".join(points) + "\n")
    with open(expected_out, "w") as out:
        json.dump(expected, out)


if __name__ == "__main__":
    main()
