#!/bin/sh
# The export benchmark: hpfc-inspect --export of world-atlas
# countries-10m to GeoPackage against the peer a user would pick, ogr2ogr
# converting the same layer from GeoJSON to GeoPackage, in the same run,
# runs interleaved (bench/export_bench.py). Then the round trip's worst
# error (tests/cli/export_oracle.py). Results: bench/README.md, "Export".
#   sh bench/run-export.sh [TOPOJSON [LAYER [RUNS]]]
# TOPOJSON defaults to countries-10m.json of the npm package world-atlas
# (cd /tmp/gis && npm install world-atlas), its layer LAYER (countries); the
# layer's GeoJSON and the packed file
# are made once into build-bench/export/ (untimed).
set -eu
cd "$(dirname "$0")/.."
src=${1:-/tmp/gis/node_modules/world-atlas/countries-10m.json}
layer=${2:-countries}
runs=${3:-7}
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench hpfc-pack/hpfc-pack hpfc-inspect/hpfc-inspect >/dev/null
dir=build-bench/export
mkdir -p "$dir"
name=$(basename "$src" .json)
geojson=$dir/$name.geojson
if [ ! -s "$geojson" ]; then
    rm -f "$geojson.tmp.geojson"
    ogr2ogr -f GeoJSON "$geojson.tmp.geojson" "$src" "$layer" && mv "$geojson.tmp.geojson" "$geojson"
fi
packed=$dir/$name.hpfc
if [ ! -s "$packed" ]; then
    build-bench/hpfc-pack/hpfc-pack --force --key name --invalid node "$geojson" -o "$packed"
fi
python3 bench/export_bench.py build-bench/hpfc-inspect/hpfc-inspect "$packed" "$geojson" "$dir" "$runs"
build-bench/hpfc-inspect/hpfc-inspect --json "$packed" >"$dir/$name.summary.json"
build-bench/hpfc-inspect/hpfc-inspect --force --export "$dir/$name.gpkg" "$packed" >/dev/null
/usr/bin/python3 tests/cli/export_oracle.py "$geojson" "$dir/$name.gpkg" "$dir/$name.summary.json" name --lenient 2>&1 |
    grep -v '^Warning 1:' ||
    echo "round trip: see the lines above"
