#!/bin/sh
# Exact point -> feature: hpfc_locate_batch on files packed with
# their exact geometry against GEOS prepared polygons in an STRtree, same
# points, same run, with agreement counts (bench/bench_locate_exact.c).
#   sh bench/run-locate-exact.sh [N] [NODE_MODULES]
# N random lattice points per layer (default 1,000,000); the layers are
# us-atlas counties-10m and world-atlas countries-10m from NODE_MODULES
# (default /tmp/x/node_modules: `cd /tmp/x && npm install us-atlas
# world-atlas`), packed with hpfc-pack's defaults (which node invalid rings) and
# a key. Release build in build-bench/. With Debian's libs2-dev installed
# (before build-bench is set up) the bench also answers with S2.
set -eu
cd "$(dirname "$0")/.."
n=${1:-1000000}
nm=${2:-/tmp/x/node_modules}
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench hpfc-pack/hpfc-pack bench/bench_locate_exact >/dev/null
dir=build-bench/exact
mkdir -p "$dir"
pack() { # NAME INPUT LAYER KEY
    [ -s "$dir/$1.hpfc" ] ||
        build-bench/hpfc-pack/hpfc-pack --quiet --layer "$3" --key "$4" "$2" -o "$dir/$1.hpfc"
}
pack counties "$nm/us-atlas/counties-10m.json" counties id
pack countries "$nm/world-atlas/countries-10m.json" countries name
for name in counties countries; do
    case $name in
    counties) src="$nm/us-atlas/counties-10m.json" ;;
    countries) src="$nm/world-atlas/countries-10m.json" ;;
    esac
    # the layer as GDAL reads it: TopoJSON's object of that name
    box=""
    [ "$name" = counties ] && box="-125 24.4 -66.9 49.4" # the conterminous United States
    # shellcheck disable=SC2086
    build-bench/bench/bench_locate_exact "$src" "$dir/$name.hpfc" "$n" 1 $box || echo "$name: exit $?"
done
