#!/bin/sh
# A GIS layer packed on a 2-worker Dask LocalCluster with its features read
# by the workers in ranges (hpfc-pack --read-range), against the same with
# the features read by hpfc-pack (--read-here), hpfc-pack alone and
# `ogr2ogr -f FlatGeobuf`, interleaved in each round (issue 32: the input
# read in parallel; bench/README.md "GIS features read by the workers").
#
#     sh bench/run-gis-ranges.sh [ROUNDS [FORMAT]]
#
# The layer is @geo-maps/countries-land-1m (250 countries, 9.5 M points,
# npm), converted once to FORMAT (GPKG, the default, or FlatGeobuf: formats
# a worker can start reading anywhere; GeoJSON is parsed whole by every
# reader). Prints each run's wall time and peaks, and checks that the three
# packs wrote the same bytes. Needs /usr/bin/python3 with dask.distributed.
set -eu
cd "$(dirname "$0")/.."
rounds=${1:-2}
format=${2:-GPKG}
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench >/dev/null
pack=$PWD/build-bench/hpfc-pack/hpfc-pack
dir=build-bench/scaling
mkdir -p "$dir"
if [ ! -d "$dir/node_modules/@geo-maps/countries-land-1m" ]; then
    (cd "$dir" && npm init -y >/dev/null && npm install --silent @geo-maps/countries-land-1m@0.6.0)
fi
layer=$dir/node_modules/@geo-maps/countries-land-1m/map.geo.json
case $format in GPKG) ext=gpkg ;; FlatGeobuf) ext=fgb ;; *) echo "FORMAT: GPKG or FlatGeobuf" >&2; exit 2 ;; esac
src=$dir/land.$ext
[ -f "$src" ] || OGR_GEOJSON_MAX_OBJ_SIZE=0 ogr2ogr -f "$format" "$src" "$layer"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# the package as the install lays it out: the built extension beside hpfc/*.py
mkdir "$work/py" "$work/py/hpfc"
ln -s "$PWD"/python/hpfc/*.py "$work/py/hpfc/"
ln -s "$PWD"/build-bench/python/_hpfc*.so "$work/py/hpfc/"
export HPFC_PACK="$pack"
for r in $(seq "$rounds"); do
    rm -f "$work"/*.hpfc "$work/out.fgb"
    /usr/bin/time -f "hpfc-pack alone: wall %e s, CPU %U+%S s, peak %M KB" \
        "$pack" -q "$src" -o "$work/alone.hpfc"
    echo "hpfc.pack, features read by hpfc-pack:"
    PYTHONPATH=$work/py /usr/bin/python3 bench/dask_pack_bench.py --read-here "$src" 8 "$work/here.hpfc"
    echo "hpfc.pack, features read by the workers:"
    PYTHONPATH=$work/py /usr/bin/python3 bench/dask_pack_bench.py "$src" 8 "$work/ranges.hpfc"
    /usr/bin/time -f "ogr2ogr -f FlatGeobuf: wall %e s, CPU %U+%S s, peak %M KB" \
        ogr2ogr -f FlatGeobuf "$work/out.fgb" "$src"
    cmp "$work/alone.hpfc" "$work/here.hpfc"
    cmp "$work/alone.hpfc" "$work/ranges.hpfc"
    echo "round $r: the same bytes"
done
