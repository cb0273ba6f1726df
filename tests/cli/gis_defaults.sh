#!/bin/sh
# hpfc-pack's defaults on real-looking GIS data:
#  1. invalid polygons are noded by default, counted in the text and JSON
#     reports with the feature named by its --key value; --invalid reject
#     refuses them, naming the feature by its key; empty geometries are
#     counted as skipped;
#  2. a layer without SRS (TopoJSON, as us-atlas ships it) whose coordinates
#     are all longitudes/latitudes is taken as WGS 84, said on stderr and in
#     the report, so that --locate-lonlat works on the file; -a_srs / -s_srs
#     set the SRS as ogr2ogr's do; --projection none keeps the coordinates;
#     an explicit --projection lcc centres on the data's median longitude,
#     also when they cross the antimeridian.
# The oracle is the input itself: the feature a point lies in, by its name.
# Skipped (exit 77) when hpfc-pack was built without GIS input.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

run "$PACK" "$TESTS/data/gis/ok/duplicate_borders.geojson" -o "$tmp/probe.hpfc"
if grep -q "not built in" "$tmp/err"; then
    echo "GIS input not built in: skipped"
    exit 77
fi

# field FILE KEY: a top-level value of the JSON object in FILE
field() {
    python3 -c 'import json,sys; v=json.load(open(sys.argv[1]))[sys.argv[2]]; print(json.dumps(v) if not isinstance(v, str) else v)' "$1" "$2" 2>/dev/null
}

# ---- 1. invalid polygons: noded by default, reported, named by key ----------
# "Bowtie" is a self-intersecting ring; "Square" is valid; one feature has
# no geometry.
cat >"$tmp/bowtie.geojson" <<'GEO'
{"type": "FeatureCollection", "features": [
 {"type": "Feature", "properties": {"name": "Square"}, "geometry": {"type": "Polygon",
  "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]]}},
 {"type": "Feature", "properties": {"name": "Bowtie"}, "geometry": {"type": "Polygon",
  "coordinates": [[[2, 0], [3, 1], [3, 0], [2, 1], [2, 0]]]}},
 {"type": "Feature", "properties": {"name": "Nothing"}, "geometry": null}
]}
GEO
run "$PACK" --key name "$tmp/bowtie.geojson" -o "$tmp/bowtie.hpfc"
expect_ok "default pack of an invalid polygon"
grep -q "^repaired   1 invalid polygon noded as linework ('Bowtie')" "$tmp/out" ||
    fail "text report does not show the repair: $(grep -E '^(repaired|skipped)' "$tmp/out")"
grep -q "^skipped    1 empty geometry, 0 point features" "$tmp/out" ||
    fail "text report does not show the skipped empty geometry"
run "$PACK" --json "$tmp/bowtie.geojson" -o "$tmp/bowtie.hpfc"
expect_ok "default pack --json"
[ "$(field "$tmp/out" invalid_polygons_noded)" = 1 ] || fail "JSON: invalid_polygons_noded != 1"
[ "$(field "$tmp/out" invalid_mode)" = node ] || fail "JSON: invalid_mode is not node"
[ "$(field "$tmp/out" skipped_empty)" = 1 ] || fail "JSON: skipped_empty != 1"
run "$PACK" --invalid reject --key name "$tmp/bowtie.geojson" -o "$tmp/reject.hpfc"
expect_error "--invalid reject" "hpfc-pack: " 1
grep -q "feature 1 (name 'Bowtie'): invalid polygon: Self-intersection" "$tmp/err" ||
    fail "--invalid reject does not name the feature by its key: $(cat "$tmp/err")"
[ -e "$tmp/reject.hpfc" ] && fail "--invalid reject left its output"
# the repaired file still answers points: inside Square
run "$INSPECT" --locate-lonlat 0.5,0.5 --json "$tmp/bowtie.hpfc"
grep -q '"fid": *0[,}]' "$tmp/out" || fail "(0.5, 0.5) is not in feature 0 (Square)"

# GEOS checks the polygons on a second thread while GDAL reads on: the
# verdicts still come in feature order. Eight bowties B0..B7 between
# squares: the report names the first four, in order, on any number of
# threads; with a point out of range after them, --invalid reject names
# B0 (which one thread meets first), not the later point, and the default
# names the point.
python3 - "$tmp" <<'PY'
import json, sys
feats = []
for k in range(8):
    x = 4 * k
    feats.append({"type": "Feature", "properties": {"name": "S%d" % k}, "geometry": {
        "type": "Polygon", "coordinates": [[[x, 0], [x + 1, 0], [x + 1, 1], [x, 1], [x, 0]]]}})
    feats.append({"type": "Feature", "properties": {"name": "B%d" % k}, "geometry": {
        "type": "Polygon", "coordinates": [[[x + 2, 0], [x + 3, 1], [x + 3, 0], [x + 2, 1], [x + 2, 0]]]}})
def dump(name, fs):
    json.dump({"type": "FeatureCollection", "features": fs}, open(sys.argv[1] + "/" + name, "w"))
dump("bowties.geojson", feats)
far = {"type": "Feature", "properties": {"name": "Far"}, "geometry": {
    "type": "LineString", "coordinates": [[0, 0], [0, 95]]}}
dump("bowties_far.geojson", feats + [far])
PY
for threads in 1 2 3; do
    run "$PACK" --threads $threads --key name "$tmp/bowties.geojson" -o "$tmp/bowties-$threads.hpfc"
    expect_ok "eight bowties on $threads threads"
    grep -qx "repaired   8 invalid polygons noded as linework ('B0', 'B1', 'B2', 'B3', ...)" "$tmp/out" ||
        fail "$threads threads: $(grep '^repaired' "$tmp/out")"
    [ "$threads" = 1 ] || cmp -s "$tmp/bowties-1.hpfc" "$tmp/bowties-$threads.hpfc" ||
        fail "eight bowties: $threads threads do not give one thread's bytes"
    run "$PACK" --threads $threads --invalid reject --key name "$tmp/bowties_far.geojson" -o "$tmp/far.hpfc"
    expect_error "--invalid reject before a later failure, $threads threads" "hpfc-pack: " 1
    grep -q "feature 1 (name 'B0'): invalid polygon: Self-intersection" "$tmp/err" ||
        fail "--invalid reject on $threads threads: $(cat "$tmp/err")"
    run "$PACK" --threads $threads --key name "$tmp/bowties_far.geojson" -o "$tmp/far.hpfc"
    expect_error "a point out of range after noded bowties, $threads threads" "hpfc-pack: " 1
    grep -q "feature 16 (name 'Far'): point (0, 95) is outside" "$tmp/err" ||
        fail "a point out of range on $threads threads: $(cat "$tmp/err")"
done

# ---- 2. no SRS: WGS 84 assumed for lon/lat coordinates -----------------------
# A TopoJSON (GDAL gives it no SRS) with two states sharing a border, and
# an island across the antimeridian from them.
cat >"$tmp/states.json" <<'TOPO'
{"type": "Topology",
 "objects": {"states": {"type": "GeometryCollection", "geometries": [
   {"type": "Polygon", "arcs": [[0, 1]], "properties": {"name": "West"}},
   {"type": "Polygon", "arcs": [[2, -1]], "properties": {"name": "East"}},
   {"type": "Polygon", "arcs": [[3]], "properties": {"name": "Island"}}]},
  "nation": {"type": "GeometryCollection", "geometries": [
   {"type": "Polygon", "arcs": [[1, 2]], "properties": {"code": "N"}}]}},
 "arcs": [[[-100, 40], [-100, 45]],
          [[-100, 45], [-110, 45], [-110, 40], [-100, 40]],
          [[-100, 40], [-90, 40], [-90, 45], [-100, 45]],
          [[172, 50], [174, 50], [174, 52], [172, 52], [172, 50]]]}
TOPO
run "$PACK" --key name -l states "$tmp/states.json" -o "$tmp/states.hpfc"
[ "$rc" -eq 0 ] || fail "TopoJSON without SRS: exit $rc: $(cat "$tmp/err")"
check oneline "$tmp/err" "hpfc-pack: note: " || fail "no one-line note on stderr"
grep -q "has no SRS .*taken as WGS 84 (EPSG:4326)" "$tmp/err" || fail "note: $(cat "$tmp/err")"
grep -q "^srs .*assumed WGS 84" "$tmp/out" || fail "the text report does not say WGS 84 was assumed"
run "$INSPECT" --locate-lonlat -95,42 --json "$tmp/states.hpfc"
expect_ok "--locate-lonlat on the TopoJSON's file"
grep -q '"key": *"East"' "$tmp/out" || fail "(-95, 42) is not in East: $(cat "$tmp/out")"
run "$INSPECT" --locate-lonlat -105,42 --json "$tmp/states.hpfc"
grep -q '"key": *"West"' "$tmp/out" || fail "(-105, 42) is not in West: $(cat "$tmp/out")"
run "$PACK" -q --json "$tmp/states.json" -o "$tmp/q.hpfc"
[ -s "$tmp/out" ] || [ -s "$tmp/err" ] && fail "-q printed something: $(cat "$tmp/out" "$tmp/err")"
run "$PACK" --json "$tmp/states.json" -o "$tmp/j.hpfc"
[ "$(field "$tmp/out" srs_assumed)" = true ] || fail "JSON: srs_assumed is not true"

# --key on layers of which only some have the field (us-atlas: 'states'
# beside 'nation'): the others' features have no key; a layer chosen with
# -l must have it
run "$PACK" --json --key name "$tmp/states.json" -o "$tmp/k.hpfc"
[ "$rc" -eq 0 ] || fail "--key name with a layer without it: exit $rc: $(cat "$tmp/err")"
[ "$(field "$tmp/out" polygon_features)" = 4 ] || fail "--key name: not 4 polygon features"
run "$INSPECT" --locate-lonlat -95,42 --json "$tmp/k.hpfc"
python3 -c '
import json, sys
a = json.load(open(sys.argv[1]))
keys = sorted((f["layer"], f.get("key")) for f in a["features"])
assert ("nation", None) in keys and ("states", "East") in keys, keys' "$tmp/out" ||
    fail "(-95, 42): not in East and in the nation without key: $(cat "$tmp/out")"
run "$PACK" -q --key name -l nation "$tmp/states.json" -o "$tmp/k2.hpfc"
expect_error "-l nation --key name" "hpfc-pack: " 1
grep -q "layer 'nation' has no such field (fields: 'id', 'code')" "$tmp/err" || fail "-l nation: $(cat "$tmp/err")"

# -a_srs: no assumption, no note; the CRS names the given SRS
run "$PACK" --json -a_srs EPSG:4269 "$tmp/states.json" -o "$tmp/a.hpfc"
expect_ok "-a_srs EPSG:4269"
case $(field "$tmp/out" crs) in *"source EPSG:4269"*) ;; *) fail "-a_srs: crs $(field "$tmp/out" crs)" ;; esac
[ "$(field "$tmp/out" srs_assumed)" = false ] || fail "-a_srs: srs_assumed is not false"
# -s_srs overrides the SRS a GeoJSON records (WGS 84) with a projected one
run "$PACK" --json -s_srs EPSG:3857 "$tmp/bowtie.geojson" -o "$tmp/s.hpfc"
expect_ok "-s_srs EPSG:3857"
[ "$(field "$tmp/out" projection)" = none ] || fail "-s_srs EPSG:3857: projected again"
case $(field "$tmp/out" crs) in *"EPSG:3857"*) ;; *) fail "-s_srs: crs $(field "$tmp/out" crs)" ;; esac
run "$PACK" -a_srs EPSG:NOPE "$tmp/states.json" -o "$tmp/bad.hpfc"
expect_error "-a_srs EPSG:NOPE" "hpfc-pack: " 1
grep -q -- "-a_srs EPSG:NOPE: not a spatial reference system" "$tmp/err" || fail "-a_srs: $(cat "$tmp/err")"
run "$PACK" -a_srs EPSG:4326 -s_srs EPSG:4326 "$tmp/states.json" -o "$tmp/bad.hpfc"
expect_error "-a_srs with -s_srs" "hpfc-pack: " 2
# --projection none: coordinates kept, nothing assumed
run "$PACK" --json --projection none "$tmp/states.json" -o "$tmp/n.hpfc"
expect_ok "--projection none"
[ "$(field "$tmp/out" crs)" = null ] || fail "--projection none: crs $(field "$tmp/out" crs)"

# --projection lcc: the central meridian at the data's median longitude,
# between -110 and -90, not at the plain extent's middle (-110+174)/2 = 32
run "$PACK" --json --projection lcc "$tmp/states.json" -o "$tmp/lcc.hpfc"
[ "$rc" -eq 0 ] || fail "--projection lcc: exit $rc: $(cat "$tmp/err")"
lon0=$(field "$tmp/out" crs | sed -n 's/.*+lon_0=\([-0-9.]*\).*/\1/p')
python3 -c "import sys; sys.exit(0 if -110 <= float(sys.argv[1]) <= -90 else 1)" "${lon0:-nan}" ||
    fail "--projection lcc: lon_0=$lon0, not on the data"
run "$INSPECT" --locate-lonlat 173,51 --json "$tmp/lcc.hpfc"
grep -q '"fid": *2[,}]' "$tmp/out" || fail "lcc: (173, 51) is not in Island: $(cat "$tmp/out")"

# ---- 3. the vertex model: junctions, shape points kept, leaves bounded -------
# (a file no larger than FlatGeobuf by default). The states' outer
# arcs have 3 shape points each, so with --leaf-points 1 the leaves holding
# them must refine further than the default's.
run "$PACK" --json "$tmp/states.json" -o "$tmp/d.hpfc"
[ "$rc" -eq 0 ] || fail "defaults: exit $rc: $(cat "$tmp/err")"
[ "$(field "$tmp/out" vertex_model)" = junctions ] ||
    fail "default vertex model: $(field "$tmp/out" vertex_model)"
[ "$(field "$tmp/out" leaf_points)" = 16 ] || fail "default leaf points: $(field "$tmp/out" leaf_points)"
run "$INSPECT" --json "$tmp/d.hpfc"
python3 -c 'import json,sys; g=json.load(open(sys.argv[1]))["exact_geometry"]; sys.exit(0 if g else 1)' "$tmp/out" ||
    fail "defaults: no exact geometry"
run "$PACK" --json --root 1 "$tmp/states.json" -o "$tmp/b16.hpfc"
refined16=$(field "$tmp/out" refined_pixels)
run "$PACK" --json --root 1 --leaf-points 1 "$tmp/states.json" -o "$tmp/b1.hpfc"
refined1=$(field "$tmp/out" refined_pixels)
[ "$refined1" -gt "$refined16" ] || fail "--leaf-points 1 refines no more than 16 ($refined1, $refined16)"
for f in b16 b1; do
    run "$INSPECT" --verify "$tmp/$f.hpfc"
    expect_ok "--verify --leaf-points file $f"
done
run "$INSPECT" --locate-lonlat -105,42.5 --json "$tmp/b1.hpfc"
grep -q '"key":"West"\|"fid":0' "$tmp/out" || fail "--leaf-points 1: (-105, 42.5) not in West: $(cat "$tmp/out")"

finish
