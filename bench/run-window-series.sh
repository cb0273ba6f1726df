#!/bin/sh
# The window query on four files of one kind growing four hundredfold, against
# FlatGeobuf's bbox read of the same window (bench/window_series.py,
# bench/README.md "Window as the file grows"):
#   sh bench/run-window-series.sh [RUNS]
# Release build in build-bench/, its Python package and GDAL plugin used
# from an install into build-bench/stage; the maps are generated, packed and
# written as FlatGeobuf once into build-bench/window-series/ (about 6 GB).
set -eu
cd "$(dirname "$0")/.."
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench >/dev/null
rm -rf build-bench/stage
meson install -C build-bench --destdir "$PWD/build-bench/stage" >/dev/null
stage=$PWD/build-bench/stage/usr/local
PYTHONPATH=$(echo "$stage"/lib/python3*/dist-packages) \
LD_LIBRARY_PATH=$stage/lib/x86_64-linux-gnu \
GDAL_DRIVER_PATH=$PWD/build-bench/gdal \
    exec /usr/bin/python3 bench/window_series.py build-bench/window-series \
    build-bench/hpfc-pack/hpfc-pack "${1:-5}"
