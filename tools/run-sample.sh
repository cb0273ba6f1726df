#!/bin/sh
# Builds hpfc and runs the main job on the sample shipped in data/: pack a
# 4000-vertex Delaunay-like map into an .hpfc file, then inspect it.
set -eu
cd "$(dirname "$0")/.."
sh tools/install-deps.sh
[ -d build ] || meson setup build --buildtype=release >/dev/null
ninja -C build >/dev/null
./build/hpfc-pack/hpfc-pack --force data/delaunay-4000.pfc -o build/delaunay-4000.hpfc
./build/hpfc-inspect/hpfc-inspect build/delaunay-4000.hpfc
