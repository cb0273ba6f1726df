"""Generated GIS inputs for tests/cli/gis_messy.sh (too large, or too many
files, to commit).

    gis_gen.py big OUT.geojson N     a MultiPolygon of N small squares (about
                                     190 bytes each), larger than a lowered
                                     OGR_GEOJSON_MAX_OBJ_SIZE, and a line
                                     through a few of them
    gis_gen.py layers DIR            DIR/{parcels,borders,roads}.geojson, three
                                     layers of one planar map
    gis_gen.py dateline OUT SEED     random features across the antimeridian:
                                     spiky star polygons (crossing it many
                                     times) with star holes, rings around a
                                     pole, lines

The layers, around (10 E, 50 N):
  parcels  a 4 x 4 grid of 0.01 degree squares sharing their borders;
  borders  the first row of parcels again, not bit-identically: a midpoint on
           every side, one square reversed and starting at another corner,
           one only as the lines of its sides;
  roads    a diagonal across the grid, a line along part of a grid line
           (overlapping a border), a dead end, and messy records: a null
           geometry, empty LineString / Polygon / GeometryCollection, a point.
Axis-parallel sides make the midpoints exactly collinear in (lon, lat), so the
oracle sees the same borders as hpfc-pack's snap rounding.
"""
import json
import math
import os
import random
import sys


def collection(feats):
    return {"type": "FeatureCollection",
            "features": [{"type": "Feature", "properties": {"i": i}, "geometry": g}
                         for i, g in enumerate(feats)]}


def big(path, n):
    # n squares of 10 m in a row: a sweep on x meets each square alone
    squares = []
    for k in range(n):
        x, y = round(-100 + k * 2e-4, 9), round(35 + (k % 7) * 1e-5, 9)
        squares.append([[[x, y], [x + 1e-4, y], [x + 1e-4, y + 1e-4], [x, y + 1e-4], [x, y]]])
    # and a line through the first 40: crossing sides, and running along the
    # bottoms of the squares it meets at y = 35.00005, so that a few
    # segments of many need noding
    line = {"type": "LineString", "coordinates": [[-100.00005, 35.00005], [-99.99205, 35.00005]]}
    with open(path, "w") as f:
        json.dump(collection([{"type": "MultiPolygon", "coordinates": squares}, line]), f,
                  separators=(",", ":"))


X = [10 + i * 0.01 for i in range(5)]
Y = [50 + j * 0.01 for j in range(5)]


def square(i, j):
    return [[X[i], Y[j]], [X[i + 1], Y[j]], [X[i + 1], Y[j + 1]], [X[i], Y[j + 1]],
            [X[i], Y[j]]]


def with_midpoints(ring):
    out = []
    for p, q in zip(ring, ring[1:]):
        out += [p, [(p[0] + q[0]) / 2 if p[0] != q[0] else p[0],
                    (p[1] + q[1]) / 2 if p[1] != q[1] else p[1]]]
    return out + [ring[-1]]


def layers(d):
    parcels = [{"type": "Polygon", "coordinates": [square(i, j)]}
               for j in range(4) for i in range(4)]
    s1 = square(1, 0)[:-1]
    rev = (s1[2:] + s1[:2])[::-1]  # another start, the other way round
    s3 = square(3, 0)
    borders = [{"type": "Polygon", "coordinates": [with_midpoints(square(0, 0))]},
               {"type": "Polygon", "coordinates": [with_midpoints(rev + [rev[0]])]},
               {"type": "Polygon", "coordinates": [square(2, 0)]},
               {"type": "MultiLineString", "coordinates": [[p, q] for p, q in zip(s3, s3[1:])]}]
    roads = [{"type": "LineString", "coordinates": [[9.995, 49.997], [10.043, 50.041]]},
             {"type": "LineString", "coordinates": [[10.005, Y[2]], [10.025, Y[2]]]},
             {"type": "LineString", "coordinates": [[X[4], 50.015], [10.032, 50.017]]},
             None,
             {"type": "LineString", "coordinates": []},
             {"type": "Polygon", "coordinates": []},
             {"type": "GeometryCollection", "geometries": []},
             {"type": "Point", "coordinates": [10.02, 50.05]}]
    for name, feats in (("parcels", parcels), ("borders", borders), ("roads", roads)):
        with open(os.path.join(d, name + ".geojson"), "w") as f:
            json.dump(collection(feats), f)


def wrap(lon):
    return lon - 360 if lon > 180 else lon + 360 if lon < -180 else lon


def star(rng, cx, cy, rmin, rmax, n):
    """A ring star-shaped around (cx, cy): no two sides cross. Angles step
    evenly, jittered by 40 %, so that with n >= 8 no side comes nearer the
    centre than rmin cos(81 / 2 degrees), 0.76 rmin: room for a hole."""
    step = 2 * math.pi / n
    angles = [k * step + rng.uniform(-0.4, 0.4) * step for k in range(n)]
    ring = []
    for a in angles:
        r = rng.uniform(rmin, rmax)
        ring.append([wrap(cx + r * math.cos(a)), cy + r * math.sin(a)])
    return ring + [ring[0]]


def dateline(path, seed):
    rng = random.Random(seed)
    feats = []
    for band in range(3):  # stars in separate latitude bands, never overlapping
        cx, cy = rng.choice([180, -180]) + rng.uniform(-3, 3), -40 + 30 * band
        rings = [star(rng, cx, cy, 4, 10, rng.randint(8, 60))]
        if rng.random() < 0.7:
            rings.append(star(rng, cx, cy, 1, 3, rng.randint(3, 20))[::-1])
        feats.append({"type": "Polygon", "coordinates": rings})
    for sign in (-1, 1):  # rings around the poles, at most one each
        if rng.random() < 0.6:
            lon, ring = -180 + rng.uniform(0, 10), []
            while lon < 180:
                ring.append([lon, sign * (75 + rng.uniform(-5, 5))])
                lon += rng.uniform(1, 30)
            feats.append({"type": "Polygon", "coordinates": [ring + [ring[0]]]})
    line = [[wrap(rng.choice([180, -180]) + rng.uniform(-8, 8)), rng.uniform(-60, 60)]
            for _ in range(rng.randint(2, 12))]
    feats.append({"type": "LineString", "coordinates": line})
    with open(path, "w") as f:
        json.dump(collection(feats), f)


if sys.argv[1] == "big":
    big(sys.argv[2], int(sys.argv[3]))
elif sys.argv[1] == "dateline":
    dateline(sys.argv[2], int(sys.argv[3]))
else:
    layers(sys.argv[2])
