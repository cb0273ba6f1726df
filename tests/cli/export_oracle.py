"""Round trip of hpfc-inspect --export against the GIS input it came from.

usage: export_oracle.py SOURCE EXPORTED SUMMARY.json KEY [--strict-rings] [--lenient]

SOURCE is the layer given to hpfc-pack (longitude/latitude or projected),
EXPORTED what hpfc-inspect --export wrote, SUMMARY.json hpfc-inspect
--json's summary of the packed file (its CRS and lattice unit). Checks,
with GDAL/OGR and GEOS as the independent side:

- the output's SRS is the source's;
- every feature of the source comes back once, as fid = its position in
  the layer, with its KEY value;
- every shape point of every source ring lies within half a lattice unit
  (per axis, in the projected plane the file records) of a point of the
  same feature's output, plus 1e-6 m for the forward and inverse projection
  (GeographicLib against PROJ); the worst distance is reported in metres
  and in degrees;
- every output geometry is valid (GEOS), and with --strict-rings the same
  number of polygons and holes as its source feature (features that reach
  the antimeridian excepted: hpfc-pack cuts them there);
- the symmetric difference of source and output, in the plane, is at most
  the source's perimeter times one lattice unit.
A source feature that is invalid (hpfc-pack nodes it: spikes and slivers
may vanish from the union of faces) has its missing points counted, not
failed; --lenient counts those of every feature (a real layer's GEOS snap
rounding in hpfc-pack may move points) and the features cut at the
antimeridian. Prints one summary line; exits 1 with the reasons on a failure.
"""
import json
import math
import sys

from osgeo import ogr, osr

ogr.UseExceptions()
osr.UseExceptions()


def fail(msgs):
    for m in msgs[:20]:
        print("export_oracle:", m, file=sys.stderr)
    sys.exit(1)


def main():
    src_path, out_path, summary_path, key = sys.argv[1:5]
    strict = "--strict-rings" in sys.argv[5:]
    lenient = "--lenient" in sys.argv[5:]
    summary = json.load(open(summary_path))
    unit = summary["lattice_unit"]["user"]
    crs = summary["crs"]
    desc = crs.split(";")[0].strip()

    src = ogr.Open(src_path)
    out = ogr.Open(out_path)
    problems = []
    sl = src.GetLayer(0)
    ol = out.GetLayer(0)
    s_srs = sl.GetSpatialRef()
    o_srs = ol.GetSpatialRef()
    geographic = s_srs is None or s_srs.IsGeographic()
    if s_srs is None:
        s_srs = osr.SpatialReference()
        s_srs.ImportFromEPSG(4326)
    s_srs.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
    if o_srs is None or not o_srs.IsSame(s_srs):
        problems.append("output SRS %s is not the source's %s" % (
            o_srs.ExportToProj4() if o_srs else None, s_srs.ExportToProj4()))

    # the plane the file's lattice lives in
    plane = osr.SpatialReference()
    plane.ImportFromProj4(desc + " +over")  # no wrapping at +-180: both sides compared
    plane.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
    to_plane = None if not geographic else osr.CoordinateTransformation(s_srs, plane)

    def project(points):
        if to_plane is None:
            return list(points)
        return [tuple(p[:2]) for p in to_plane.TransformPoints(points)]

    outputs = {}
    for f in ol:
        fid = f.GetField("fid") if f.GetFieldIndex("fid") >= 0 else f.GetFID()
        if fid in outputs:
            problems.append("fid %d written twice" % fid)
        g = f.GetGeometryRef()
        outputs[fid] = (g.Clone() if g else None, f.GetField(key) if key != "-" else None)

    worst_m = worst_deg = 0.0
    points = far = 0
    ring_mismatch = invalid = skipped = loose_missing = noded_missing = 0
    for k, f in enumerate(sl):
        g = f.GetGeometryRef()
        if g is None or g.IsEmpty():
            continue
        if k not in outputs:
            problems.append("feature %d missing" % k)
            continue
        og, okey = outputs[k]
        polys = [g.GetGeometryRef(i) for i in range(g.GetGeometryCount())] \
            if g.GetGeometryType() in (ogr.wkbMultiPolygon, ogr.wkbMultiPolygon25D) else [g]
        seam = geographic and any(abs(x) >= 179.999 for p in polys
                                  for r in range(p.GetGeometryCount())
                                  for x, *_ in p.GetGeometryRef(r).GetPoints())
        # a source hpfc-pack had to node (--invalid node): its spikes and
        # slivers may rightly vanish from the union of faces, so its points
        # are counted, not required (features cut at the antimeridian are
        # invalid in plane lon/lat too: required unless --lenient)
        loose = not g.IsValid() and (lenient or not seam)
        skipped += loose
        if key != "-" and str(okey) != str(f.GetField(key)):
            problems.append("feature %d: key %r, source %r" % (k, okey, f.GetField(key)))
        if og is None:
            problems.append("feature %d: no geometry" % k)
            continue
        if not og.IsValid():
            invalid += 1
            problems.append("feature %d: invalid output geometry" % k)
        # the output's points in the plane, by lattice cell
        opts = []
        for poly in range(og.GetGeometryCount()):
            p = og.GetGeometryRef(poly)
            for r in range(p.GetGeometryCount()):
                opts.extend(p.GetGeometryRef(r).GetPoints())
        ll = list(opts)
        if geographic:  # a point on the antimeridian may come back on its other side
            ll += [(x - 360.0 * math.copysign(1, x), y) for x, y, *_ in opts if abs(x) > 179.999]
        cells = {}
        for (px, py), (lx, ly, *_) in zip(project([(p[0], p[1]) for p in ll]), ll):
            cells.setdefault((math.floor(px / unit), math.floor(py / unit)), []).append(
                (px, py, lx, ly))
        spts = []
        touches_seam = False
        holes = 0
        for p in polys:
            holes += p.GetGeometryCount() - 1
            for r in range(p.GetGeometryCount()):
                ring = p.GetGeometryRef(r).GetPoints()
                spts.extend(ring)
                touches_seam |= geographic and any(abs(x) >= 179.999 for x, *_ in ring)
        for (px, py), (lx, ly, *_) in zip(project([(p[0], p[1]) for p in spts]), spts):
            cx, cy = math.floor(px / unit), math.floor(py / unit)
            best = None
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    for qx, qy, qlx, qly in cells.get((cx + dx, cy + dy), ()):
                        d = max(abs(qx - px), abs(qy - py))
                        if best is None or d < best[0]:
                            best = (d, qlx, qly, math.hypot(qx - px, qy - py))
            points += 1
            if best is None or best[0] > 0.5 * unit + 1e-6:
                if loose:
                    loose_missing += 1
                    continue
                if lenient:  # GEOS's snap rounding in hpfc-pack may have moved it
                    noded_missing += 1
                    continue
                far += 1
                if far <= 5:
                    problems.append("feature %d: source point (%.9f, %.9f) has no output point "
                                    "within half a lattice unit (nearest %s)" % (
                                        k, lx, ly, "none" if best is None else "%.3g units away" % (best[0] / unit)))
                continue
            worst_m = max(worst_m, best[3])
            if geographic:
                dlon = abs(best[1] - lx)
                dlon = min(dlon, 360.0 - dlon)
                worst_deg = max(worst_deg, dlon, abs(best[2] - ly))
        npoly = og.GetGeometryCount()
        ohole = sum(og.GetGeometryRef(i).GetGeometryCount() - 1 for i in range(npoly))
        if strict and not touches_seam and not loose and (npoly != len(polys) or ohole != holes):
            ring_mismatch += 1
            problems.append("feature %d: %d polygons and %d holes, source %d and %d" % (
                k, npoly, ohole, len(polys), holes))
        if not touches_seam and not loose:
            a = g.Clone()
            b = og.Clone()
            if to_plane is not None:
                a.Transform(to_plane)
                b.Transform(to_plane)
            if a.IsValid() and b.IsValid():
                diff = a.SymDifference(b).GetArea()
                bound = a.Boundary().Length() * unit
                if diff > bound:
                    problems.append("feature %d: symmetric difference %.6g > %.6g" % (k, diff, bound))
    if problems:
        fail(problems)
    print("%d source points, %d within half a lattice unit (%g) of their feature's output: "
          "worst %.3g m%s; %d features, all valid; %d invalid in the source (noded): %d of "
          "their points not in the output%s" % (
              points, points - loose_missing - noded_missing, unit, worst_m,
              ", %.3g degrees" % worst_deg if geographic else "", len(outputs), skipped,
              loose_missing,
              "; %d points of valid sources not in the output (--lenient: hpfc-pack's noding)"
              % noded_missing if lenient else ""))


main()
