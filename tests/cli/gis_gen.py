"""Generated GIS inputs for tests/cli/gis_messy.sh (too large, or too many
files, to commit).

    gis_gen.py big OUT.geojson N     a MultiPolygon of N small squares (about
                                     190 bytes each), larger than a lowered
                                     OGR_GEOJSON_MAX_OBJ_SIZE, and a line
                                     through a few of them
    gis_gen.py layers DIR            DIR/{parcels,borders,roads}.geojson, three
                                     layers of one planar map

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
import os
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


if sys.argv[1] == "big":
    big(sys.argv[2], int(sys.argv[3]))
else:
    layers(sys.argv[2])
