#!/bin/sh
# The GIS packing benchmark: hpfc-pack on a synthetic continental
# coverage of about 4 million shape points (bench/gen_continent.py), as
# GeoJSON and, when ogr2ogr is there, FlatGeobuf and GeoPackage, in both
# vertex models. Prints one row per run (bench/gis_bench.py). Called by bench/run.sh; on its own:
#   sh bench/run-gis.sh [COLS ROWS POINTS_PER_SIDE]
# The data is generated once into build-bench/gis/ (about 130 MB of GeoJSON
# at the defaults; delete the folder to make it again).
set -eu
cd "$(dirname "$0")/.."
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench hpfc-pack/hpfc-pack >/dev/null
dir=build-bench/gis
mkdir -p "$dir"
name=continent${1:+-$1x$2x$3}
src=$dir/$name.geojson
if [ ! -s "$src" ]; then
    python3 bench/gen_continent.py "$src.tmp" "$@" && mv "$src.tmp" "$src"
fi
inputs=$src
if command -v ogr2ogr >/dev/null 2>&1; then
    for fmt in FlatGeobuf:fgb GPKG:gpkg; do
        out=$dir/$name.${fmt#*:}
        tmpout=$dir/tmp.${fmt#*:} # the drivers go by the suffix
        if [ ! -s "$out" ]; then
            rm -rf "$tmpout"
            ogr2ogr -f "${fmt%:*}" "$tmpout" "$src" -nln continent && mv "$tmpout" "$out"
        fi
        inputs="$inputs $out"
    done
fi
# one process each, since peak RSS is per process; both vertex models
head="cat"
for model in all junctions; do
    for f in $inputs; do
        python3 bench/gis_bench.py build-bench/hpfc-pack/hpfc-pack "$dir" \
            --vertices="$model" "$f" | $head
        head="tail -n +2"
    done
done
