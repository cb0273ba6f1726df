#!/bin/sh
# Builds the benchmarks in release mode (build-bench/) and runs them all,
# printing the tables recorded in bench/README.md. Takes a few minutes
# (the GIS data is generated on the first run).
# One case per process: peak RSS (getrusage) is a whole-process figure.
set -eu
cd "$(dirname "$0")/.."
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench bench/bench_build bench/bench_traverse bench/bench_read >/dev/null
# bench_locate exists only with the GIS dependencies (not built by default)
ninja -C build-bench bench/bench_locate >/dev/null 2>&1 || true
B=build-bench/bench/bench_build

cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -1)
mem=$(awk '/^MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo 2>/dev/null || true)
echo "machine: ${cpu:-unknown CPU}, $(nproc) cores, ${mem:-? GiB} RAM, $(uname -sr)"
echo "compiler: $(cc --version | head -1); meson --buildtype=release; date $(date -u +%Y-%m-%d)"
echo

echo "(a) builder throughput: hpfc_build (validation included) on one core, median of 3;"
echo "    rss_in = peak RSS after generating the graph, rss = peak after the builds,"
echo "    B/seg = (rss - rss_in) / segments; (n0, n) = (64, 2)"
$B --header grid
for c in "grid 424" "grid 600" "delaunay 150000" "delaunay 300000"; do
    # shellcheck disable=SC2086 # $c is a kind and a size
    $B $c
done
echo

echo "(b) the paper's experiment (Sect. 6): 4000 random points, Delaunay, 20% of edges"
echo "    removed, (n0, n) = (64, 2); rPFC = the flat grid in which no edge lies in one pixel"
$B --header paper
$B paper 5
echo

echo "(c) traversal: BFS over all darts by next and twin on the hPFC file, the"
echo "    flat rPFC file and a half-edge array (next[], twin[]) of the same map; on the hPFC"
echo "    file also by 64-bit keys (hpfc_key_next, hpfc_key_twin)"
build-bench/bench/bench_traverse 5 1
echo

echo "(d) reader: open cost on a 671 MB file, pixel fetch + decode, deep locate"
build-bench/bench/bench_read
echo

echo "(e) GIS packing: hpfc-pack on a synthetic continental coverage, stages in"
echo "    seconds, peak RSS against the input file's size"
sh bench/run-gis.sh
echo

# (e) needs the GIS dependencies (bench_locate is built only with them)
if [ -x build-bench/bench/bench_locate ]; then
    echo "(f) point in feature: hpfc --locate path (hpfc_locate, the leaf's faces, their"
    echo "    FEAT features) against GEOS prepared polygons in an STRtree, same random points of"
    echo "    the projected extent; set-up ms (faces numbered / polygons prepared), ns per point,"
    echo "    share of private leaves, share of answers that agree"
    ninja -C build-bench hpfc-pack/hpfc-pack >/dev/null
    tmp=$(mktemp -d)
    printf '%-28s %8s %9s | %9s %9s | %9s %9s | %7s %7s\n' layer features points \
        hpfc_ms hpfc_ns geos_ms geos_ns private agree
    for layer in tests/data/gis/counties_ne.geojson; do
        build-bench/hpfc-pack/hpfc-pack --quiet --force --key name "$layer" -o "$tmp/l.hpfc"
        build-bench/bench/bench_locate "$layer" "$tmp/l.hpfc" 200000 1
    done
    rm -rf "$tmp"
fi
