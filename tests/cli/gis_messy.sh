#!/bin/sh
# Messy GIS input (hpfc-pack/gis_input.c) made by gis_gen.py at test time:
#  - one GeoJSON feature larger than GDAL's object-size limit (lowered here
#    to 1 MB through the environment, as GDAL itself then refuses it): read
#    all the same, since hpfc-pack lifts the limit; a line across some of it
#    makes GEOS node only those segments (noding "partial");
#  - random polygons crossing the antimeridian many times, with holes, rings
#    around a pole, lines: cut as gis_oracle.py cuts them;
#  - three layers of one map in a GeoPackage (made with ogr2ogr; skipped when
#    gdal-bin is missing): borders stored twice non-identically, lines along
#    and across them, null / empty geometries and a point; merged into one
#    planar graph, and one or two of them chosen with --layer;
#  - a GML file packed twice: the same bytes, and nothing written beside it.
# Counts are checked against gis_oracle.py on the same GeoJSON files, with the
# linear projections (eqc, none): the oracle works in longitude/latitude, and
# only they keep a vertex lying on another feature's side in (lon, lat) on it.
# Skipped (exit 77) when hpfc-pack was built without GIS input.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
GEN="python3 $HERE/gis_gen.py"

run "$PACK" "$TESTS/data/gis/ok/duplicate_borders.geojson" -o "$tmp/probe.hpfc"
if grep -q "not built in" "$tmp/err"; then
    echo "GIS input not built in: skipped"
    exit 77
fi

# agree WHAT ORACLE_JSON: the last report's counts are the oracle's, in the
# report's vertex model
agree() {
    python3 - "$tmp/out" "$2" <<'PY' || fail "$1: counts differ from gis_oracle.py"
import json, sys
r = json.load(open(sys.argv[1]))
o = json.load(open(sys.argv[2]))[r["vertex_model"]]
bad = [f"{k} {r[k]} != {o[k]}" for k in ("vertices", "edges", "faces", "components") if r[k] != o[k]]
if bad:
    print("; ".join(bad))
    sys.exit(1)
PY
}

# want WHAT KEY VALUE: a field of the last report
want() {
    got=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1])).get(sys.argv[2]))' "$tmp/out" "$2")
    [ "$got" = "$3" ] || fail "$1: $2 is $got, expected $3"
}

# packs WHAT ORACLE_JSON ARGS...: packs in both vertex models and compares
packs() {
    what=$1
    oracle=$2
    shift 2
    for model in all junctions; do
        run "$PACK" --json --vertices "$model" "$@" -o "$tmp/m.hpfc"
        expect_ok "$what --vertices $model"
        [ "$rc" -eq 0 ] && agree "$what --vertices $model" "$oracle"
    done
}

# 1. a feature over GDAL's object-size limit
$GEN big "$tmp/big.geojson" 8000
python3 "$HERE/gis_oracle.py" "$tmp/big.geojson" >"$tmp/big.json"
if command -v ogrinfo >/dev/null 2>&1 &&
    OGR_GEOJSON_MAX_OBJ_SIZE=1 ogrinfo -ro -so "$tmp/big.geojson" >/dev/null 2>&1; then
    fail "big.geojson: GDAL reads it under a 1 MB limit; the test proves nothing"
fi
OGR_GEOJSON_MAX_OBJ_SIZE=1
export OGR_GEOJSON_MAX_OBJ_SIZE
packs "big feature" "$tmp/big.json" --projection eqc "$tmp/big.geojson"
unset OGR_GEOJSON_MAX_OBJ_SIZE
# the line makes a few segments of thousands need noding: GEOS nodes those
want "big feature" noding partial

# 2. random features across the antimeridian: the cut against the oracle's
for seed in 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20; do
    $GEN dateline "$tmp/dl.geojson" "$seed"
    python3 "$HERE/gis_oracle.py" "$tmp/dl.geojson" >"$tmp/dl.json"
    packs "dateline seed $seed" "$tmp/dl.json" "$tmp/dl.geojson"
done

# 3. layers, first each GeoJSON on its own
mkdir "$tmp/lay"
$GEN layers "$tmp/lay"
for f in parcels borders roads; do
    python3 "$HERE/gis_oracle.py" "$tmp/lay/$f.geojson" >"$tmp/$f.json"
    packs "$f.geojson" "$tmp/$f.json" --projection eqc "$tmp/lay/$f.geojson"
done
want "roads.geojson" skipped_empty 4
want "roads.geojson" skipped_points 1

if ! command -v ogr2ogr >/dev/null 2>&1; then
    echo "ogr2ogr not found (tools/install-deps.sh installs gdal-bin): GeoPackage checks skipped"
    finish
fi
gpkg=$tmp/lay/map.gpkg
for f in parcels borders roads; do
    update=""
    [ -f "$gpkg" ] && update=-update
    ogr2ogr -f GPKG $update "$gpkg" "$tmp/lay/$f.geojson" -nln "$f" 2>"$tmp/ogr.err" ||
        fail "ogr2ogr $f: $(cat "$tmp/ogr.err")"
done
python3 "$HERE/gis_oracle.py" "$tmp/lay/parcels.geojson" "$tmp/lay/borders.geojson" \
    "$tmp/lay/roads.geojson" >"$tmp/all.json"
python3 "$HERE/gis_oracle.py" "$tmp/lay/parcels.geojson" "$tmp/lay/roads.geojson" >"$tmp/pr.json"
for proj in eqc none; do
    packs "map.gpkg ($proj)" "$tmp/all.json" --projection "$proj" "$gpkg"
    want "map.gpkg ($proj)" layers_read 3
    want "map.gpkg ($proj)" input_format GPKG
done
want "map.gpkg" skipped_empty 4
packs "map.gpkg --layer roads" "$tmp/roads.json" --projection eqc --layer roads "$gpkg"
want "map.gpkg --layer roads" layers_read 1
packs "map.gpkg --layer parcels --layer roads" "$tmp/pr.json" --projection eqc \
    --layer parcels --layer roads "$gpkg"
want "map.gpkg --layer parcels --layer roads" layers_read 2
run "$PACK" --layer rivers "$gpkg" -o "$tmp/m.hpfc"
expect_error "map.gpkg --layer rivers" "hpfc-pack: " 1
grep -q "no layer 'rivers' (layers: 'parcels', 'borders', 'roads')" "$tmp/err" ||
    fail "map.gpkg --layer rivers: $(cat "$tmp/err")"

# 4. packing reads only: GDAL's GML driver, left to itself, writes a .gfs
#    schema beside a GML file without one and reads it back the next time
#    (so a second pack of the same file differed from the first)
mkdir "$tmp/gml"
ogr2ogr -f GML -dsco XSISCHEMA=OFF "$tmp/gml/borders.gml" "$tmp/lay/borders.geojson" \
    2>"$tmp/ogr.err" || fail "ogr2ogr GML: $(cat "$tmp/ogr.err")"
before=$(ls "$tmp/gml")
packs "borders.gml" "$tmp/borders.json" --projection eqc "$tmp/gml/borders.gml"
cp "$tmp/m.hpfc" "$tmp/first.hpfc"
packs "borders.gml, again" "$tmp/borders.json" --projection eqc "$tmp/gml/borders.gml"
[ "$(ls "$tmp/gml")" = "$before" ] || fail "borders.gml: packing wrote $(ls "$tmp/gml" | tr '\n' ' ')"
cmp -s "$tmp/m.hpfc" "$tmp/first.hpfc" || fail "borders.gml: two packs of one file differ"

finish
