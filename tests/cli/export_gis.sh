#!/bin/sh
# hpfc-inspect --export / --export-faces (interfaces §5):
# the round trip input -> hpfc-pack -> --export through GDAL gives back every
# source shape point within half a lattice unit (plus the projection's
# error) and the same rings per feature (export_oracle.py, GDAL/GEOS on the
# other side), in both pool layouts and through several drivers; the faces
# of a .pfc fixture come back as polygons of its own points; the summary
# states the lattice unit; bad requests fail with one line and leave no
# output. Skipped (exit 77) without GIS input or Python's GDAL bindings.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
GIS=$TESTS/data/gis

run "$PACK" "$GIS/ok/duplicate_borders.geojson" -o "$tmp/probe.hpfc"
if grep -q "not built in" "$tmp/err"; then
    echo "GIS input not built in: skipped"
    exit 77
fi
py=
for cand in python3 /usr/bin/python3; do
    if "$cand" -c 'from osgeo import ogr' 2>/dev/null; then
        py=$cand
        break
    fi
done
if [ -z "$py" ]; then
    echo "no python3 with osgeo (python3-gdal): skipped"
    exit 77
fi

# roundtrip NAME SOURCE EXT KEY [PACK OPTIONS...]: pack, export to OUT.EXT,
# compare with the source
roundtrip() {
    name=$1 source=$2 ext=$3 key=$4
    shift 4
    run "$PACK" "$@" "$source" -o "$tmp/$name.hpfc"
    expect_ok "$name: pack"
    run "$INSPECT" --json "$tmp/$name.hpfc"
    cp "$tmp/out" "$tmp/$name.summary.json"
    run "$INSPECT" --export "$tmp/$name.$ext" --json "$tmp/$name.hpfc"
    expect_ok "$name: --export $name.$ext"
    cp "$tmp/out" "$tmp/$name.export.json"
    run "$py" "$HERE/export_oracle.py" "$source" "$tmp/$name.$ext" "$tmp/$name.summary.json" \
        "$key" $strict
    if [ "$rc" -ne 0 ]; then
        fail "$name: round trip: $(head -c 600 "$tmp/err")"
    else
        echo "$name: $(cat "$tmp/out")"
    fi
}

world=$GIS/countries_world.geojson
strict=--strict-rings
roundtrip world "$world" gpkg name --key name
roundtrip world_paper "$world" geojson name --key name --layout paper
roundtrip world_fields "$world" fgb name --fields all
roundtrip utm "$GIS/ok/projected_utm.geojson" gpkg i --key i
strict=
roundtrip counties "$GIS/counties_ne.geojson" gpkg name --key name --invalid node
roundtrip counties_junctions "$GIS/counties_ne.geojson" geojson name --key name --invalid node \
    --vertices junctions --layout paper

# what the export says: the world goes back to EPSG:4326, lon/lat
python3 - "$tmp/world.export.json" <<'PY' || fail "--export --json summary"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["driver"] == "GPKG" and r["srs"] == "EPSG:4326" and r["projected_back"], r
assert r["written"] == 22 and r["polygons"] >= 22 and r["points"] > 1000, r
PY
python3 - "$tmp/utm.export.json" <<'PY' || fail "--export of a projected source"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["srs"] == "EPSG:32618" and not r["projected_back"], r
PY
# attributes travel: --fields all keeps id and name
"$py" - "$tmp/world_fields.fgb" <<'PY' || fail "--export --fields all: attributes"
import sys
from osgeo import ogr
ds = ogr.Open(sys.argv[1])  # kept: its layers die with it
layer = ds.GetLayer(0)
names = [layer.GetLayerDefn().GetFieldDefn(i).GetName() for i in range(layer.GetLayerDefn().GetFieldCount())]
assert "fid" in names and "source_fid" in names and "id" in names and "name" in names, names
rows = {f.GetField("fid"): (f.GetField("id"), f.GetField("name")) for f in layer}
assert rows[0] == ("710", "South Africa"), rows[0]
PY

# the lattice unit, in user units and metres
run "$INSPECT" "$tmp/world.hpfc"
grep -q "^unit       1 lattice unit = .* user units = .* m (metres of the projected plane)" "$tmp/out" ||
    fail "summary: no lattice unit in metres: $(grep unit "$tmp/out")"
grep -q "^geometry   exact" "$tmp/out" || fail "summary: exact geometry not stated"
python3 -c 'import json,sys; u=json.load(open(sys.argv[1]))["lattice_unit"]; assert u["metres"] == u["user"] > 0, u' \
    "$tmp/world.summary.json" || fail "--json: lattice_unit"

# --export-faces of .pfc fixtures, both pool layouts: every face a valid
# polygon of the file's own points, all bounded faces there, and (but for
# the dead ends of crack_dead_end and loop, which bound no face) every
# input point in them
for fx in two_components_hole square_diagonal multi_edges loop crack_dead_end polyline_decimals; do
    for layout in compact paper; do
        run "$PACK" --json --layout $layout "$TESTS/data/valid/$fx.pfc" -o "$tmp/$fx.hpfc"
        cp "$tmp/out" "$tmp/$fx.report.json"
        run "$INSPECT" --export-faces "$tmp/$fx.geojson" "$tmp/$fx.hpfc"
        expect_ok "$fx ($layout): --export-faces"
        "$py" - "$TESTS/data/valid/$fx.pfc" "$tmp/$fx.geojson" "$tmp/$fx.report.json" "$fx" <<'PY' || fail "$fx ($layout): --export-faces"
import json, sys
from osgeo import ogr
pts = set()
for line in open(sys.argv[1]):
    f = line.split("#")[0].split()
    if f and f[0] == "v":
        pts.add((float(f[1]), float(f[2])))
    elif f and f[0] == "e":
        pts.update((float(f[k]), float(f[k + 1])) for k in range(3, len(f) - 1, 2))
faces = json.load(open(sys.argv[3]))["faces"]
ds = ogr.Open(sys.argv[2])  # kept: its layers die with it
layer = ds.GetLayer(0)
seen, found = set(), set()
close = lambda a, b: abs(a - b) <= 1e-9 * max(1, abs(b))
for ft in layer:
    g = ft.GetGeometryRef()
    assert g.IsValid(), ft.GetField("face")
    seen.add(ft.GetField("face"))
    for r in range(g.GetGeometryCount()):
        for x, y, *_ in g.GetGeometryRef(r).GetPoints():
            match = [p for p in pts if close(x, p[0]) and close(y, p[1])]
            assert match, (x, y)
            found.update(match)
assert seen == set(range(1, faces)), (sorted(seen), faces)
missing = pts - found
assert not missing or sys.argv[4] in ("crack_dead_end", "loop"), sorted(missing)[:5]
PY
    done
done

# refusals: one line, exit status, nothing left behind
run "$INSPECT_BIN" --export "$tmp/world.gpkg" "$tmp/world.hpfc"
expect_error "existing OUT without --force" "hpfc-inspect: $tmp/world.gpkg: exists" 1
mkdir "$tmp/empty"
run "$INSPECT" --export "$tmp/empty/x.gpkg" -f NoSuchDriver "$tmp/world.hpfc"
expect_error "-f unknown" "hpfc-inspect: -f NoSuchDriver: no such GDAL driver" 1
run "$INSPECT" --export "$tmp/empty/x.nosuchext" "$tmp/world.hpfc"
expect_error "unknown extension" "hpfc-inspect: $tmp/empty/x.nosuchext: no GDAL vector driver" 1
run "$INSPECT" --export "$tmp/empty/x.gpkg" "$TESTS/data/valid/borders_features.hpfc"
expect_error "a file without GEOM" "hpfc-inspect: $TESTS/data/valid/borders_features.hpfc: no exact geometry" 1
run "$INSPECT" --export "$tmp/empty/x.gpkg" "$tmp/two_components_hole.hpfc"
expect_error "a file without features" "hpfc-inspect: $tmp/two_components_hole.hpfc: the file has no features" 1
run "$INSPECT" --export "$tmp/nosuchdir/x.gpkg" "$tmp/world.hpfc"
expect_error "OUT in a missing directory" "hpfc-inspect: $tmp/nosuchdir/x.gpkg: cannot create a temporary directory" 1
[ -z "$(ls -A "$tmp/empty")" ] || fail "failed exports left files: $(ls -A "$tmp/empty")"
run "$INSPECT" -f GPKG "$tmp/world.hpfc"
expect_error "-f without --export" "hpfc-inspect: -f: only with --export or --export-faces" 2
# a Shapefile is several files, all moved into place
run "$INSPECT" --export "$tmp/empty/w.shp" "$tmp/world.hpfc"
expect_ok "--export .shp"
for s in shp shx dbf prj; do
    [ -f "$tmp/empty/w.$s" ] || fail "--export .shp: no w.$s"
done
[ "$(ls -A "$tmp/empty" | grep -c '^\.')" -eq 0 ] || fail "--export .shp left a temporary directory"

finish
