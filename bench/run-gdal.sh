#!/bin/sh
# The GDAL driver's benchmark (bench/README.md, "The GDAL driver"): the
# same reads from .hpfc (through the plugin) and from FlatGeobuf, same run,
# interleaved (bench/gdal_bench.py):
#   ogr2ogr -f GPKG of us-atlas counties-10m,
#   ogrinfo -spat over a window holding about 1 % of the counties, against
#   a full read of the layer and against FlatGeobuf's indexed bbox read,
#   geopandas.read_file of world-atlas countries-10m (against FlatGeobuf
#   with and without the SRS the .hpfc carries), as whole processes and
#   then in one interpreter (the read alone, imports paid once);
#   then the `ogrinfo -spat` and `geopandas.read_file` pairs against
#   FlatGeobuf with the same SRS, back to back, PAIRS of each
#   (bench/gdal_pairs.py: the ratio a pair, its median and quartiles).
#   sh bench/run-gdal.sh [NODE_MODULES [RUNS [PAIRS]]]
# NODE_MODULES holds us-atlas and world-atlas (default
# build-bench/npm/node_modules: `cd build-bench/npm && npm install us-atlas
# world-atlas`). The build is build-bench (release) unless HPFC_BENCH_BUILD
# names another; both layers are packed with hpfc-pack's defaults and
# `--key name --fields all`, as FlatGeobuf gets every field.
set -eu
cd "$(dirname "$0")/.."
build=${HPFC_BENCH_BUILD:-build-bench}
[ -d "$build" ] || meson setup "$build" --buildtype=release >/dev/null
ninja -C "$build" hpfc-pack/hpfc-pack gdal/ogr_HPFC.so >/dev/null
nm=${1:-build-bench/npm/node_modules}
dir=$build/gdal-bench
mkdir -p "$dir"
export GDAL_DRIVER_PATH=$PWD/$build/gdal
pack() { # NAME TOPOJSON LAYER
    [ -s "$dir/$1.hpfc" ] || "$build/hpfc-pack/hpfc-pack" -q --key name --fields all -l "$3" "$2" -o "$dir/$1.hpfc"
    [ -s "$dir/$1.fgb" ] || ogr2ogr -f FlatGeobuf "$dir/$1.fgb" "$2" "$3"
}
pack counties "$nm/us-atlas/counties-10m.json" counties
# FlatGeobuf from TopoJSON carries no SRS, the .hpfc EPSG:4326 (hpfc-pack's
# reading of lon/lat input), and creating any SRS opens PROJ's database
# (about 9 ms, once a process): the same SRS for the fair pair
[ -s "$dir/counties_srs.fgb" ] || ogr2ogr -f FlatGeobuf -a_srs EPSG:4326 "$dir/counties_srs.fgb" \
    "$nm/us-atlas/counties-10m.json" counties
pack countries "$nm/world-atlas/countries-10m.json" countries
[ -s "$dir/countries_srs.fgb" ] || ogr2ogr -f FlatGeobuf -a_srs EPSG:4326 "$dir/countries_srs.fgb" \
    "$nm/world-atlas/countries-10m.json" countries
/usr/bin/python3 bench/gdal_bench.py "$dir" "${2:-7}"
/usr/bin/python3 bench/gdal_pairs.py "$dir" "${3:-20}"
