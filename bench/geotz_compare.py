#!/usr/bin/env python3
"""Answers of hpfc, geo-tz and shapely at the same points, for
bench/run-geotz.sh.

    geotz_compare.py SOURCE.geojson POINTS.txt HPFC.jsonl GEOTZ.jsonl

SOURCE: the decoded map (one feature a tile piece or covered cell, tzid);
POINTS: lon,lat lines; HPFC: hpfc-inspect --locate-batch --lonlat's
answers; GEOTZ: bench/geotz_find.js's. Counts, for every point, whether
hpfc's features are exactly the source polygons that hold the point
(shapely, an STRtree over the source), and whether hpfc's zones (its
features' tzids, or geo-tz's own zone at sea where no feature holds the
point) are geo-tz's; every disagreement is printed with the point's
distance to the nearest border of the polygons involved, in metres.
"""
import json
import math
import sys

from shapely.geometry import Point, shape
from shapely.strtree import STRtree

# geo-tz's oceanZones (src/oceanUtils.ts): (tzid, left, right)
OCEAN = [
    ('Etc/GMT-12', 172.5, 180),
    ('Etc/GMT-11', 157.5, 172.5),
    ('Etc/GMT-10', 142.5, 157.5),
    ('Etc/GMT-9', 127.5, 142.5),
    ('Etc/GMT-8', 112.5, 127.5),
    ('Etc/GMT-7', 97.5, 112.5),
    ('Etc/GMT-6', 82.5, 97.5),
    ('Etc/GMT-5', 67.5, 82.5),
    ('Etc/GMT-4', 52.5, 67.5),
    ('Etc/GMT-3', 37.5, 52.5),
    ('Etc/GMT-2', 22.5, 37.5),
    ('Etc/GMT-1', 7.5, 22.5),
    ('Etc/GMT', -7.5, 7.5),
    ('Etc/GMT+1', -22.5, -7.5),
    ('Etc/GMT+2', -37.5, -22.5),
    ('Etc/GMT+3', -52.5, -37.5),
    ('Etc/GMT+4', -67.5, -52.5),
    ('Etc/GMT+5', -82.5, -67.5),
    ('Etc/GMT+6', -97.5, -82.5),
    ('Etc/GMT+7', -112.5, -97.5),
    ('Etc/GMT+8', -127.5, -112.5),
    ('Etc/GMT+9', -142.5, -127.5),
    ('Etc/GMT+10', -157.5, -142.5),
    ('Etc/GMT+11', -172.5, -157.5),
    ('Etc/GMT+12', -180, -172.5),
]


def ocean_zones(lon):
    """geo-tz's getTimezoneAtSea."""
    if lon in (-180, 180):
        return {"Etc/GMT+12", "Etc/GMT-12"}
    return {z for z, left, right in OCEAN if left <= lon <= right}


def main(src, points, hpfc, geotz):
    feats = json.load(open(src))["features"]
    geoms = [shape(f["geometry"]) for f in feats]
    tzid = [f["properties"]["tzid"] for f in feats]
    index = {id(g): k for k, g in enumerate(geoms)}
    tree = STRtree(geoms)
    pts = [tuple(map(float, line.split(",")[:2])) for line in open(points) if line.strip()]
    ours = [json.loads(line) for line in open(hpfc)]
    theirs = [set(json.loads(line)) for line in open(geotz)]
    assert len(pts) == len(ours) == len(theirs), (len(pts), len(ours), len(theirs))
    bad_src = bad_tz = 0
    worst = []
    for (lon, lat), a, t in zip(pts, ours, theirs):
        p = Point(lon, lat)
        want = {index[id(g)] for g in tree.query(p) if g.covers(p)}
        got = {f["fid"] for f in a.get("features", [])}
        zones = {tzid[k] for k in got} or ocean_zones(lon)
        if got != want or zones != t:
            near = min((geoms[k].boundary.distance(p) for k in got ^ want), default=0.0)
            worst.append((near * 111_320 * max(math.cos(math.radians(lat)), 1e-9)
                          if got != want else None, lon, lat, sorted(got), sorted(want),
                          sorted(zones), sorted(t)))
        bad_src += got != want
        bad_tz += zones != t
    print(json.dumps({"points": len(pts), "disagree_with_source": bad_src,
                      "disagree_with_geotz": bad_tz}))
    for w in worst[:20]:
        print("  disagreement:", w)


if __name__ == "__main__":
    main(*sys.argv[1:5])
