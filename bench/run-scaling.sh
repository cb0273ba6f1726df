#!/bin/sh
# How every whole-file call grows with the map (bench/README.md, "Scaling"):
# hpfc-pack's stages, hpfc_faces_build, hpfc_shapes_feature_polygons (the
# largest feature, every feature), hpfc-inspect --export, --export-faces, --verify,
# --render and the batch point location, each at three sizes of three
# kinds of map (world countries from npm: world-atlas@2 and
# @geo-maps/countries-land-1m, fetched into build-bench/scaling/ on the
# first run; bench/gen_continent.py and bench/gen_archipelago.py at 10^5,
# 10^6 and 10^7 shape points, generated once), with the exponent between
# sizes (bench/scaling.py).
#   sh bench/run-scaling.sh [--record]         release build in build-bench/
#   sh bench/run-scaling.sh smoke [--record]   CI's guard (below)
# smoke: two small generated maps (2*10^4 and 10^5 points), every stage
# counted in instructions by callgrind in a release build that keeps the
# stages' functions out of line (build-smoke/), the exponents compared with
# bench/scaling-exponents.json; fails naming the stage whose exponent grew.
# --record writes the exponents measured into that file.
set -eu
cd "$(dirname "$0")/.."
mode=full
if [ "${1:-}" = smoke ]; then
    mode=smoke
    shift
fi
targets="hpfc-pack/hpfc-pack hpfc-inspect/hpfc-inspect bench/bench_shapes bench/bench_locate_batch"
py=python3
python3 -c 'from osgeo import ogr' 2>/dev/null || py=/usr/bin/python3
if [ $mode = smoke ]; then
    sh tools/install-deps.sh # valgrind among them
    build=build-smoke
    # inlining a function called once would hide the stage it is from the profile
    [ -d $build ] || meson setup $build --buildtype=release -Dpython=disabled \
        -Dc_args=-fno-inline-functions-called-once >/dev/null
    ninja -C $build $targets >/dev/null
    exec $py bench/scaling.py smoke $build $build/scaling "$@"
fi
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench $targets >/dev/null
dir=build-bench/scaling
mkdir -p "$dir"
if [ ! -d "$dir/node_modules/@geo-maps/countries-land-1m" ]; then
    (cd "$dir" && npm init -y >/dev/null &&
        npm install --silent world-atlas@2.0.2 @geo-maps/countries-land-1m@0.6.0)
fi
exec $py bench/scaling.py full build-bench "$dir" "$@"
