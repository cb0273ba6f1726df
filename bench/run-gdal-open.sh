#!/bin/sh
# The GDAL driver's open and 1 % window in one process, against FlatGeobuf
# (bench/gdal_open_bench.py; bench/README.md, "The shape index"):
#   sh bench/run-gdal-open.sh [RUNS]
# us-atlas counties from build-bench/gdal-bench (sh bench/run-gdal.sh makes
# them), then the window series' large and huge maps where
# build-bench/window-series has them (sh bench/run-window-series.sh).
set -eu
cd "$(dirname "$0")/.."
build=${HPFC_BENCH_BUILD:-build-bench}
ninja -C "$build" gdal/ogr_HPFC.so >/dev/null
export GDAL_DRIVER_PATH=$PWD/$build/gdal
runs=${1:-15}
g=$build/gdal-bench
/usr/bin/python3 bench/gdal_open_bench.py "$runs" counties -102.1 37.0 -99.5 39.0 \
    "$g/counties.hpfc" "$g/counties_srs.fgb"
w=$build/window-series
for size in large huge; do
    [ -s "$w/$size.hpfc" ] && [ -s "$w/$size.fgb" ] || continue
    layer=$(ogrinfo -ro -q "$w/$size.fgb" | sed -n 's/^1: \([^ ]*\).*/\1/p')
    # the window of bench/window_series.py
    window=$(/usr/bin/python3 -c "import sys; sys.path.insert(0, 'bench'); import series_window as s; print(*s.WINDOW)")
    /usr/bin/python3 bench/gdal_open_bench.py "$runs" "$layer" $window \
        "$w/$size.hpfc" "$w/$size.fgb"
done
