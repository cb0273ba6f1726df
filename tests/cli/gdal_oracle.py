"""The OGR driver HPFC against independent readings (gdal_driver.sh's files).

Usage: gdal_oracle.py TMP. TMP holds, for M in sample, counties, world and
lines: M.hpfc, M.export.gpkg (hpfc-inspect --export, not for the sample),
M.faces.gpkg (--export-faces), M.gpkg (ogr2ogr -f GPKG of every layer),
M.geojson (ogr2ogr -f GeoJSON of the faces), M.so.txt (ogrinfo -al -so);
and where.txt, spat.txt (ogrinfo -where / -spat on counties), back.hpfc
(the driver's GPKG of counties packed again). Prints one line per failure
and exits 1 if any.
"""

import json
import os
import random
import re
import struct
import subprocess
import sys

import fiona
import geopandas
import shapely.wkb
from shapely.ops import unary_union
from shapely.geometry import box, Polygon
from osgeo import gdal, ogr

gdal.UseExceptions()
ogr.UseExceptions()

TMP = sys.argv[1]
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


def path(name):
    return os.path.join(TMP, name)


def features(layer):
    """{fid: (fields dict, WKB bytes or None)} of a layer read in order."""
    out = {}
    layer.ResetReading()
    for f in layer:
        g = f.GetGeometryRef()
        out[f.GetFID()] = (f.items(), bytes(g.ExportToIsoWkb()) if g else None)
    return out


def get_feature(layer, fid):
    """layer.GetFeature(fid), None where GDAL raises for a missing fid."""
    try:
        return layer.GetFeature(fid)
    except RuntimeError:
        return None


def open_hpfc(name, **kw):
    return gdal.OpenEx(path(name), gdal.OF_VECTOR, allowed_drivers=["HPFC"], **kw)


MAPS = ["sample", "counties", "world", "lines", "two"]
# each map's source layers; "two" is counties and their borders as lines,
# two layers of one GeoPackage (each layer typed on its own)
SOURCE = {"counties": ["counties_ne"], "world": ["countries_world"], "lines": ["lines_crossing"],
          "two": ["polys", "borders"]}

# ---- the layers, their fields and their features, against hpfc-inspect --export ----
for m in MAPS:
    ds = open_hpfc(m + ".hpfc")
    names = [ds.GetLayer(i).GetName() for i in range(ds.GetLayerCount())]
    want = SOURCE.get(m, []) + ["faces", "edges"]
    if names != want:
        fail(f"{m}: layers {names}, expected {want}")
        continue
    so = open(path(m + ".so.txt")).read()
    for n in want:
        if f"Layer name: {n}" not in so:
            fail(f"{m}: ogrinfo -so does not show layer {n}")
    if m in SOURCE:
        ref = gdal.OpenEx(path(m + ".export.gpkg"), gdal.OF_VECTOR)
        for n in SOURCE[m]:
            a, b = ds.GetLayerByName(n), ref.GetLayerByName(n)
            da, db = a.GetLayerDefn(), b.GetLayerDefn()
            fa = [(da.GetFieldDefn(i).GetName(), da.GetFieldDefn(i).GetType()) for i in range(da.GetFieldCount())]
            fb = [(db.GetFieldDefn(i).GetName(), db.GetFieldDefn(i).GetType()) for i in range(db.GetFieldCount())]
            if fa != fb:
                fail(f"{m}/{n}: fields {fa}, --export has {fb}")
            if a.GetSpatialRef() is None or not a.GetSpatialRef().IsSame(b.GetSpatialRef()):
                fail(f"{m}/{n}: SRS differs from --export's")
            xa, xb = features(a), features(b)
            # the layer's type against its features' geometries as read
            kinds = {ogr.CreateGeometryFromWkb(w).GetGeometryType() for _, w in xa.values() if w}
            want_type = (ogr.wkbMultiPolygon if kinds == {ogr.wkbMultiPolygon} else
                         ogr.wkbMultiLineString if kinds <= {ogr.wkbMultiLineString} else
                         ogr.wkbUnknown)
            if a.GetGeomType() != want_type:
                fail(f"{m}/{n}: geometry type {ogr.GeometryTypeToName(a.GetGeomType())}, "
                     f"its features hold {sorted(ogr.GeometryTypeToName(k) for k in kinds)}")
            if xa != xb:
                diff = [k for k in set(xa) | set(xb) if xa.get(k) != xb.get(k)]
                fail(f"{m}/{n}: {len(diff)} features differ from --export's (fids {sorted(diff)[:5]})")
            if a.GetFIDColumn() != "fid":
                fail(f"{m}/{n}: FID column '{a.GetFIDColumn()}'")
    # faces against --export-faces
    ref = gdal.OpenEx(path(m + ".faces.gpkg"), gdal.OF_VECTOR)
    fa, fb = features(ds.GetLayerByName("faces")), features(ref.GetLayer(0))
    if fa != fb:
        diff = [k for k in set(fa) | set(fb) if fa.get(k) != fb.get(k)]
        fail(f"{m}/faces: {len(diff)} faces differ from --export-faces' (ids {sorted(diff)[:5]})")
    # edges: each lies on the boundary of the faces it names, with their features
    # every point of a face's rings: an edge's points are among them, exactly
    faces = {}
    for fid, (_, w) in fa.items():
        poly = shapely.wkb.loads(w)
        faces[fid] = {c for ring in [poly.exterior, *poly.interiors] for c in ring.coords}
    face_fids = {fid: it.get("fids", "") for fid, (it, _) in fa.items()}
    edges = features(ds.GetLayerByName("edges"))
    bad = 0
    for e, (it, w) in edges.items():
        line = shapely.wkb.loads(w)
        if it["left_face"] == it["right_face"]:
            continue  # a dead end or bridge inside a face: no part of its rings
        for side in ("left", "right"):
            face = it[side + "_face"]
            if face == 0:
                if m in SOURCE and it[side + "_fids"] != "":
                    bad += 1
                continue
            if face not in faces or not set(line.coords) <= faces[face]:
                bad += 1
            elif m in SOURCE and it[side + "_fids"] != face_fids[face]:
                bad += 1
    if bad:
        fail(f"{m}/edges: {bad} edge sides disagree with the faces layer")
    if not edges:
        fail(f"{m}/edges: none")
    # ---- random reads, counts, extents, capabilities ----
    for i in range(ds.GetLayerCount()):
        layer = ds.GetLayer(i)
        n = layer.GetName()
        for cap in (ogr.OLCRandomRead, ogr.OLCFastFeatureCount, ogr.OLCFastGetExtent,
                    ogr.OLCFastSpatialFilter):
            if not layer.TestCapability(cap):
                fail(f"{m}/{n}: {cap} false")
        seq = features(layer)
        if layer.GetFeatureCount() != len(seq):
            fail(f"{m}/{n}: GetFeatureCount {layer.GetFeatureCount()}, {len(seq)} read")
        fids = list(seq)
        random.Random(7).shuffle(fids)
        for fid in fids[:300]:
            f = layer.GetFeature(fid)
            g = f.GetGeometryRef()
            if f is None or (f.items(), bytes(g.ExportToIsoWkb()) if g else None) != seq[fid]:
                fail(f"{m}/{n}: GetFeature({fid}) differs from the sequential read")
                break
        for fid in (max(seq) + 1, -5):
            if get_feature(layer, fid) is not None:
                fail(f"{m}/{n}: GetFeature({fid}) found a feature")
        x0, x1, y0, y1 = layer.GetExtent()
        env = unary_union([shapely.wkb.loads(w) for _, w in seq.values() if w]).bounds
        if not (x0 <= env[0] and y0 <= env[1] and x1 >= env[2] and y1 >= env[3]):
            fail(f"{m}/{n}: extent {(x0, y0, x1, y1)} does not hold the features' {env}")
        if n == "edges" and max(abs(a - b) for a, b in zip((x0, y0, x1, y1), env)) > 0:
            fail(f"{m}/{n}: extent {(x0, y0, x1, y1)}, the edges' is {env}")

        # ---- spatial filters against GEOS on the shapes read ----
        shapes = {fid: shapely.wkb.loads(w) for fid, (_, w) in seq.items() if w}
        rng = random.Random(hash((m, n)) & 0xFFFF)
        ex0, ey0, ex1, ey1 = env
        w, h = ex1 - ex0, ey1 - ey0
        for trial in range(25):
            ax, bx = sorted(rng.uniform(ex0 - 0.1 * w, ex1 + 0.1 * w) for _ in range(2))
            ay, by = sorted(rng.uniform(ey0 - 0.1 * h, ey1 + 0.1 * h) for _ in range(2))
            if trial % 3 == 0:  # small windows: the 1 % case
                bx, by = ax + 0.05 * w, ay + 0.05 * h
            if trial % 5 == 4:
                tri = Polygon([(ax, ay), (bx, ay), (ax, by)])
                layer.SetSpatialFilter(ogr.CreateGeometryFromWkb(tri.wkb))
                want = {fid for fid, s in shapes.items() if s.intersects(tri)}
            else:
                layer.SetSpatialFilterRect(ax, ay, bx, by)
                want = {fid for fid, s in shapes.items() if s.intersects(box(ax, ay, bx, by))}
            got = set(features(layer))
            if layer.GetFeatureCount() != len(want):
                fail(f"{m}/{n}: filtered count {layer.GetFeatureCount()}, GEOS says {len(want)}")
            layer.SetSpatialFilter(None)
            if got != want:
                fail(f"{m}/{n}: window {(ax, ay, bx, by)} trial {trial}: {len(got)} features, "
                     f"GEOS says {len(want)} (missing {sorted(want - got)[:5]}, extra {sorted(got - want)[:5]})")
                break

        # ---- ignored fields: no geometry, or a field unset, the rest as read ----
        names = [layer.GetLayerDefn().GetFieldDefn(i).GetName()
                 for i in range(layer.GetLayerDefn().GetFieldCount())]
        for ignored in (["OGR_GEOMETRY"], names[:1]):
            if not ignored or layer.SetIgnoredFields(ignored) != 0:
                if ignored:
                    fail(f"{m}/{n}: SetIgnoredFields({ignored}) refused")
                continue
            part = features(layer)
            def without(it):
                return {k: v for k, v in it.items() if k not in ignored}
            drop_geom = ignored == ["OGR_GEOMETRY"]
            if sorted(part) != sorted(seq) or any(
                    without(part[k][0]) != without(seq[k][0]) or
                    part[k][1] != (None if drop_geom else seq[k][1]) or
                    any(part[k][0].get(x) is not None for x in ignored) for k in part):
                fail(f"{m}/{n}: with {ignored} ignored the features differ from the full read")
            if drop_geom and seq:
                fid = next(iter(seq))
                f = layer.GetFeature(fid)
                if f is None or f.GetGeometryRef() is not None:
                    fail(f"{m}/{n}: GetFeature({fid}) with the geometry ignored")
                # a spatial filter still tests each feature's geometry, then drops it
                ax, ay = ex0 + 0.3 * w, ey0 + 0.3 * h
                want = {fid for fid, s in shapes.items() if s.intersects(box(ax, ay, ax + 0.2 * w, ay + 0.2 * h))}
                layer.SetSpatialFilterRect(ax, ay, ax + 0.2 * w, ay + 0.2 * h)
                got = features(layer)
                layer.SetSpatialFilter(None)
                if set(got) != want or any(g is not None for _, g in got.values()):
                    fail(f"{m}/{n}: a window with the geometry ignored gives {len(got)} features, "
                         f"GEOS says {len(want)}")
            layer.SetIgnoredFields([])
    # ---- ogr2ogr's GPKG and GeoJSON hold the same features ----
    gp = gdal.OpenEx(path(m + ".gpkg"), gdal.OF_VECTOR)
    for i in range(ds.GetLayerCount()):
        n = ds.GetLayer(i).GetName()
        a, b = features(ds.GetLayer(i)), features(gp.GetLayerByName(n))
        if a != b:
            fail(f"{m}/{n}: ogr2ogr -f GPKG changed {sum(a.get(k) != b.get(k) for k in set(a) | set(b))} features")
    gj = json.load(open(path(m + ".geojson")))
    fl = features(ds.GetLayerByName("faces"))
    if len(gj["features"]) != len(fl):
        fail(f"{m}: GeoJSON faces {len(gj['features'])}, driver {len(fl)}")
    # in order: GeoJSON keeps the ids only where the driver has fields to carry
    for feat, (it, _) in zip(gj["features"], fl.values()):
        if dict(feat["properties"]) != it:
            fail(f"{m}: GeoJSON face {feat['properties']} differs from {it}")
            break

# ---- ogrinfo -where and -spat on counties ----
ds = open_hpfc("counties.hpfc")
layer = ds.GetLayerByName("counties_ne")
allf = features(layer)
names = sorted(re.findall(r"^  name \(String\) = (.*)$", open(path("where.txt")).read(), re.M))
want = sorted(it["name"] for it, _ in allf.values() if it["name"].startswith("New"))
if names != want or not want:
    fail(f"ogrinfo -where: {names}, expected {want}")
spat = sorted(int(x) for x in re.findall(r"^OGRFeature\(counties_ne\):(\d+)$", open(path("spat.txt")).read(), re.M))
want = sorted(fid for fid, (_, w) in allf.items() if shapely.wkb.loads(w).intersects(box(-73, 41, -72, 42)))
if spat != want or not want:
    fail(f"ogrinfo -spat: {spat}, expected {want}")

# ---- attribute filters through osgeo: alone, on the geometry, with a window ----
def filtered(layer, where, rect=None):
    layer.SetAttributeFilter(where)
    if rect:
        layer.SetSpatialFilterRect(*rect)
    got = features(layer)
    layer.SetAttributeFilter(None)
    layer.SetSpatialFilter(None)
    return got


got = filtered(layer, "name LIKE 'New%' OR fips LIKE '48%'")
want = {k: v for k, v in allf.items() if v[0]["name"].startswith("New") or str(v[0].get("fips")).startswith("48")}
if got != want or not want:
    fail(f"SetAttributeFilter: {len(got)} features, expected {len(want)} (or their fields or shapes differ)")
areas = sorted(shapely.wkb.loads(w).area for _, w in allf.values())
cut = (areas[len(areas) // 2] + areas[len(areas) // 2 + 1]) / 2
got = filtered(layer, f"OGR_GEOM_AREA > {cut!r}")
want = {k: v for k, v in allf.items() if shapely.wkb.loads(v[1]).area > cut}
if got != want or not want:
    fail(f"SetAttributeFilter on OGR_GEOM_AREA: {len(got)} features, expected {len(want)}")
ex = unary_union([shapely.wkb.loads(w) for _, w in allf.values()]).bounds
rect = (ex[0] + 0.2 * (ex[2] - ex[0]), ex[1] + 0.2 * (ex[3] - ex[1]),
        ex[0] + 0.7 * (ex[2] - ex[0]), ex[1] + 0.7 * (ex[3] - ex[1]))
got = filtered(layer, "fips LIKE '24%'", rect)  # digits: no question of case
want = {k: v for k, v in allf.items()
        if str(v[0]["fips"]).startswith("24") and shapely.wkb.loads(v[1]).intersects(box(*rect))}
if got != want or not want:
    fail(f"attribute filter and window: {len(got)} features, expected {len(want)}")
# ---- SetNextByIndex: the index-th feature of the read, filtered or not ----
order = list(allf)
for i in (0, 1, len(order) // 2, len(order) - 1):
    layer.ResetReading()
    if layer.SetNextByIndex(i) != 0 or layer.GetNextFeature().GetFID() != order[i]:
        fail(f"SetNextByIndex({i}) does not give the {i}-th feature")
try:
    past = layer.SetNextByIndex(len(order))
except RuntimeError:
    past = 1  # refused: raised under gdal.UseExceptions()
if past == 0 and layer.GetNextFeature() is not None:
    fail("SetNextByIndex past the end gives a feature")
layer.SetAttributeFilter("name LIKE 'New%'")
subset = [k for k in order if allf[k][0]["name"].startswith("New")]
layer.ResetReading()
if layer.SetNextByIndex(2) != 0 or layer.GetNextFeature().GetFID() != subset[2]:
    fail("SetNextByIndex with an attribute filter does not count the filtered features")
layer.SetAttributeFilter(None)

# ---- packed again from the driver's GPKG: the same features, same shapes ----
back_ds = open_hpfc("back.hpfc")  # the dataset outlives its layer (Python's GDAL)
back = back_ds.GetLayerByName("counties_ne")
b = features(back)
if sorted(b) != sorted(allf) or any(b[k][0] != allf[k][0] for k in b):
    fail("back.hpfc: other features or attributes")
else:
    worst = max(shapely.wkb.loads(w).hausdorff_distance(shapely.wkb.loads(allf[k][1]))
                for k, (_, w) in b.items())
    if worst > 1e-6:
        fail(f"back.hpfc: shapes moved by {worst} degrees")

# ---- fiona and geopandas, bbox= included ----
# fiona opens only the drivers its table names: one line adds GDAL's HPFC
fiona.supported_drivers["HPFC"] = "r"
for m, n in (("counties", "counties_ne"), ("world", "countries_world"), ("sample", "faces")):
    if fiona.listlayers(path(m + ".hpfc")) != ([n] if m != "sample" else []) + ["faces", "edges"]:
        fail(f"{m}: fiona.listlayers {fiona.listlayers(path(m + '.hpfc'))}")
    df = geopandas.read_file(path(m + ".hpfc"), layer=n, engine="fiona")
    ref_ds = open_hpfc(m + ".hpfc")
    ref = features(ref_ds.GetLayerByName(n))
    if len(df) != len(ref):
        fail(f"{m}: geopandas read {len(df)} rows, the driver has {len(ref)}")
    geoms = [shapely.wkb.loads(w) for _, w in ref.values()]
    if not all(a.equals_exact(b, 0) for a, b in zip(df.geometry, geoms)):
        fail(f"{m}: geopandas geometries differ from osgeo's")
    if df.crs is None and m != "sample":
        fail(f"{m}: geopandas sees no CRS")
    x0, y0, x1, y1 = unary_union(geoms).bounds
    c = geoms[len(geoms) // 2].representative_point()
    bb = (c.x - 0.05 * (x1 - x0), c.y - 0.05 * (y1 - y0), c.x + 0.05 * (x1 - x0), c.y + 0.05 * (y1 - y0))
    sub = geopandas.read_file(path(m + ".hpfc"), layer=n, engine="fiona", bbox=bb)
    want = sum(g.intersects(box(*bb)) for g in geoms)
    if len(sub) != want or want == 0:
        fail(f"{m}: geopandas bbox= read {len(sub)} rows, GEOS says {want}")

# ---- fids out of file order: GetFeature finds each, a repeated fid its first ----
# FEAT's records are rewritten in place (spec 6.2.1: a 32-byte header, 8 bytes a
# layer, then 24 bytes a feature, its i64 fid first), descending and with one
# fid twice; the file is opened without the section checksums it no longer
# matches (the header's still holds).
with open(path("counties.hpfc"), "rb") as f:
    data = bytearray(f.read())
feat = int(open(path("counties.feat")).read())
count, _, _, layers = struct.unpack_from("<4I", data, feat)
records = feat + 32 + 8 * layers
new_fids = [7 * (count - k) + 3 for k in range(count)]
new_fids[count // 2 + 1] = new_fids[count // 2]  # repeated: the first in file order wins
for k, fid in enumerate(new_fids):
    struct.pack_into("<q", data, records + 24 * k, fid)
with open(path("shuffled.hpfc"), "wb") as f:
    f.write(data)
ds = open_hpfc("shuffled.hpfc", open_options=["VERIFY_CHECKSUMS=NO"])
layer = ds.GetLayer(0)
order = [(f.GetFID(), f.items()) for f in layer]
if [fid for fid, _ in order] != new_fids:
    fail("shuffled fids: the sequential read does not give the rewritten fids in file order")
first = {}
for fid, items in order:
    first.setdefault(fid, items)
for fid in random.Random(11).sample(sorted(first), min(200, len(first))) + [new_fids[count // 2]]:
    f = layer.GetFeature(fid)
    if f is None or f.GetFID() != fid or f.items() != first[fid]:
        fail(f"shuffled fids: GetFeature({fid}) is not the first feature with that fid")
        break
for fid in (0, 1, new_fids[0] + 1, new_fids[-1] - 1, 4):
    if get_feature(layer, fid) is not None:
        fail(f"shuffled fids: GetFeature({fid}) found a feature where none has that fid")
ds = None

# ---- damaged files: an error, never a crash ----
src = open(path("counties.hpfc"), "rb").read()
rng = random.Random(30)
errors = opened = 0
gdal.PushErrorHandler("CPLQuietErrorHandler")
for k in range(300):
    data = bytearray(src)
    if k % 10 == 9:
        data = data[: rng.randrange(len(data))]
    else:
        for _ in range(1 + k % 4):
            data[rng.randrange(len(data))] = rng.randrange(256)
    name = f"/vsimem/damaged{k}.hpfc"
    gdal.FileFromMemBuffer(name, bytes(data))
    opts = ["VERIFY_CHECKSUMS=NO"] if k % 2 else []
    try:
        ds = gdal.OpenEx(name, gdal.OF_VECTOR, allowed_drivers=["HPFC"], open_options=opts)
    except RuntimeError as e:
        ds = None
        errors += 1
        if not str(e):
            fail(f"damaged file {k}: refused without a message")
    if ds is not None:
        opened += 1
        for i in range(ds.GetLayerCount()):
            layer = ds.GetLayer(i)
            try:
                for f in layer:
                    pass
                layer.SetSpatialFilterRect(-75, 40, -72, 42)
                for f in layer:
                    pass
                layer.GetExtent()
            except RuntimeError:
                errors += 1
        ds = None
    gdal.Unlink(name)
gdal.PopErrorHandler()
if errors == 0:
    fail("no damaged file gave an error")
# a file that only looks like one by its name, and one cut short, from the tools
with open(path("notmagic.hpfc"), "wb") as f:
    f.write(b"not an hpfc file\n" * 10)
with open(path("cut.hpfc"), "wb") as f:
    f.write(src[:200])
for name, expect in (("notmagic.hpfc", "Unable to open"), ("cut.hpfc", "HPFC")):
    r = subprocess.run(["ogrinfo", "-ro", "-al", "-so", path(name)], capture_output=True, text=True)
    if r.returncode != 1 or expect not in r.stdout + r.stderr:
        fail(f"ogrinfo {name}: exit {r.returncode}, output {(r.stdout + r.stderr).strip()[:200]}")

print(f"damaged files: {opened} opened, {errors} errors, no crash")
if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("gdal_oracle: all checks passed")
