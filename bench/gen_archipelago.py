#!/usr/bin/env python3
"""The shape that made linking faces to features quadratic: a
large coastline ring with very many small islands and lakes inside its
bounding box, like a 1:10m world land layer.

    gen_archipelago.py N OUT.fgb [COAST_POINTS]

writes a FlatGeobuf layer (EPSG:3857 metres, so hpfc-pack keeps the
coordinates) of
  - one "coast" feature: a star-shaped ring of COAST_POINTS points (default
    max(2000, N / 10)), radius about 1000 km, with N/2 lakes (hexagons on a
    grid inside it): the first HOLES (2000) are holes of the coast, the
    others lake features of their own, 1000 to a MultiPolygon, lying in the
    coast (GEOS 3.11's validity check tests every hole against the whole
    shell, so 10^5 holes in one shell would cost minutes before any linking);
    one lake in ten holds an island, a polygon of its own;
  - N/2 islands outside the coast but inside its box (its four corners),
    hexagons on a grid, 1000 to a MultiPolygon feature.
So the file has about N small parts of 7 points each, all inside the coast's
bounding box: linking them by point-in-ring tests costs N x COAST_POINTS.
No two rings meet. Deterministic (no randomness).
"""
import math
import struct
import sys

from osgeo import ogr, osr

R = 1_000_000.0  # coast radius, metres
HOLES = 2000


def hexagon(cx, cy, r, ccw):
    pts = [(cx + r * math.cos(math.pi / 3 * k), cy + r * math.sin(math.pi / 3 * k)) for k in range(6)]
    if not ccw:
        pts.reverse()
    pts = [(round(x, 1), round(y, 1)) for x, y in pts]
    return pts + [pts[0]]


def coast_ring(n):
    pts = []
    for k in range(n):
        a = 2 * math.pi * k / n
        r = R * (0.97 + 0.03 * math.sin(37 * a) * math.cos(11 * a))
        pts.append((round(r * math.cos(a), 1), round(r * math.sin(a), 1)))
    return pts + [pts[0]]


def ring_wkb(pts):
    return struct.pack("<I", len(pts)) + b"".join(struct.pack("<dd", x, y) for x, y in pts)


def polygon_wkb(rings):
    return struct.pack("<BII", 1, 3, len(rings)) + b"".join(ring_wkb(r) for r in rings)


def multipolygon_wkb(polys):
    return struct.pack("<BII", 1, 6, len(polys)) + b"".join(polygon_wkb(p) for p in polys)


def grid(count, x0, y0, x1, y1):
    """About `count` cell centres of a square grid over the box, and the cell size."""
    area = (x1 - x0) * (y1 - y0)
    s = math.sqrt(area / max(count, 1))
    nx, ny = max(1, int((x1 - x0) / s)), max(1, int((y1 - y0) / s))
    return [(x0 + (i + 0.5) * s, y0 + (j + 0.5) * s) for j in range(ny) for i in range(nx)], s


def main():
    n = int(sys.argv[1])
    out = sys.argv[2]
    coast_points = int(sys.argv[3]) if len(sys.argv) > 3 else max(2000, n // 10)
    drv = ogr.GetDriverByName("FlatGeobuf")
    ogr.UseExceptions()
    ds = drv.CreateDataSource(out)
    srs = osr.SpatialReference()
    srs.ImportFromEPSG(3857)
    layer = ds.CreateLayer("archipelago", srs, ogr.wkbMultiPolygon, ["SPATIAL_INDEX=NO"])
    layer.CreateField(ogr.FieldDefn("kind", ogr.OFTString))
    defn = layer.GetLayerDefn()

    def add(kind, wkb):
        f = ogr.Feature(defn)
        f.SetField("kind", kind)
        f.SetGeometryDirectly(ogr.CreateGeometryFromWkb(wkb))
        layer.CreateFeature(f)

    # lakes: a grid inside the square inscribed in 0.9 R
    h = 0.9 * R / math.sqrt(2)
    centres, s = grid(n // 2, -h, -h, h, h)
    centres = centres[: n // 2]
    lakes = [hexagon(cx, cy, s / 4, False) for cx, cy in centres]
    add("coast", multipolygon_wkb([[coast_ring(coast_points)] + lakes[:HOLES]]))
    for k in range(HOLES, len(lakes), 1000):
        add("lakes", multipolygon_wkb([[ring[::-1]] for ring in lakes[k:k + 1000]]))
    for k, (cx, cy) in enumerate(centres):
        if k % 10 == 0:  # an island in the lake
            add("lake island", multipolygon_wkb([[hexagon(cx, cy, s / 8, True)]]))
    # islands: the corners of the box, outside the coast (radius > 1.01 R)
    want = n // 2
    corner, s2 = grid(int(want / 0.15) + 4, -R, -R, R, R)
    spots = [(x, y) for x, y in corner if math.hypot(x, y) > 1.02 * R + s2][:want]
    batch = []
    for cx, cy in spots:
        batch.append([hexagon(cx, cy, s2 / 4, True)])
        if len(batch) == 1000:
            add("islands", multipolygon_wkb(batch))
            batch = []
    if batch:
        add("islands", multipolygon_wkb(batch))
    ds = None
    print(f"{out}: {len(lakes)} lakes, {len(centres[::10])} lake islands, {len(spots)} islands, "
          f"coast of {coast_points} points", file=sys.stderr)


if __name__ == "__main__":
    main()
