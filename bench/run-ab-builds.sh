#!/bin/sh
# Same-run A/B of two builds of the library, for changes that must not be
# slower (issue 19's refactor):
#   sh bench/run-ab-builds.sh BUILD_A BUILD_B [ROUNDS]
# BUILD_A and BUILD_B are release build directories (meson setup X
# --buildtype=release) of two commits. bench_read and bench_traverse run
# ROUNDS times each (default 5), the builds alternated, and each figure's
# median is printed with the ratio B/A. Wall times drift with the machine's
# load; with valgrind installed, the instructions of one fetch + decode
# (both layouts) and of a whole bench_traverse run do not, so they come
# last and are the figures to trust on a shared machine.
set -eu
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: sh bench/run-ab-builds.sh BUILD_A BUILD_B [ROUNDS]" >&2; exit 2; }
A=$1 B=$2 ROUNDS=${3:-5}
for build in "$A" "$B"; do
    ninja -C "$build" bench/bench_read bench/bench_traverse >/dev/null
done
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
i=0
while [ "$i" -lt "$ROUNDS" ]; do
    for side in A B; do
        eval "build=\$$side"
        "$build/bench/bench_read" | sed "s/^/$side /" >> "$OUT/read"
        for layout in paper compact; do
            "$build/bench/bench_traverse" 2 0 "$layout" | sed "s/^/$side $layout /" >> "$OUT/traverse"
        done
    done
    i=$((i + 1))
done
echo "load after:  $(cut -d' ' -f1-3 /proc/loadavg)"
if command -v valgrind >/dev/null 2>&1; then
    for side in A B; do
        eval "build=\$$side"
        for layout in paper compact; do
            for r in 0 10; do
                valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null \
                    "$build/bench/bench_read" fetch "$layout" "$r" 2> "$OUT/cg.$side.$layout.$r" > /dev/null
            done
            valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null \
                "$build/bench/bench_traverse" 1 0 "$layout" 2> "$OUT/cg.$side.$layout.walk" > /dev/null
        done
    done
fi
python3 - "$OUT" <<'PY'
import os, statistics, sys
sys.path.insert(0, "bench")
from ab_figures import FETCHES_PER_10_ROUNDS as N, cachegrind_count, read_figures, traverse_figures
out = sys.argv[1]
figures = {}  # (figure, side) -> values
for (side,), name, layout, ns in read_figures(out + "/read", prefixed=1):
    figures.setdefault((f"{name}, {layout}", side), []).append(ns)
for (side, layout), name, ns in traverse_figures(out + "/traverse", prefixed=2):
    figures.setdefault((f"{name}, {layout}", side), []).append(ns)
print(f"{'figure (ns, median of runs)':36s} {'A':>9s} {'B':>9s} {'B/A':>6s}  runs")
for (name, side), a in sorted(figures.items()):
    if side != "A" or (name, "B") not in figures:
        continue
    b = figures[(name, "B")]
    ma, mb = statistics.median(a), statistics.median(b)
    print(f"{name:36s} {ma:9.1f} {mb:9.1f} {mb / ma:6.2f}  {len(a)}")
if os.path.exists(f"{out}/cg.A.paper.0"):
    print("instructions (cachegrind)                  A            B    B/A")
    for layout in ("paper", "compact"):
        per = {s: (cachegrind_count(f"{out}/cg.{s}.{layout}.10") - cachegrind_count(f"{out}/cg.{s}.{layout}.0")) / N
               for s in "AB"}
        print(f"  one fetch + decode, {layout:8s} {per['A']:12.1f} {per['B']:12.1f} {per['B'] / per['A']:6.3f}")
        walk = {s: cachegrind_count(f"{out}/cg.{s}.{layout}.walk") for s in "AB"}
        print(f"  bench_traverse 1 0, {layout:8s} {walk['A']:12d} {walk['B']:12d} {walk['B'] / walk['A']:6.3f}")
else:
    print("valgrind not installed: no instruction counts")
PY
