#!/bin/sh
# Same-run A/B of two builds of the library, for changes that must not be
# slower (refactor):
#   sh bench/run-ab-builds.sh BUILD_A BUILD_B [ROUNDS [FILE.hpfc]]
# BUILD_A and BUILD_B are release build directories (meson setup X
# --buildtype=release) of two commits. bench_read and bench_traverse run
# ROUNDS times each (default 5), the builds alternated, and each figure's
# median is printed with the ratio B/A. With FILE, the tools' traversals
# too: hpfc-inspect --export-graph and --verify on FILE, alternated the
# same way, their outputs compared (they must be identical). Wall times drift with the machine's
# load; with valgrind installed, the instructions of one fetch + decode
# (both layouts) and of a whole bench_traverse run do not, so they come
# last and are the figures to trust on a shared machine.
set -eu
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: sh bench/run-ab-builds.sh BUILD_A BUILD_B [ROUNDS [FILE.hpfc]]" >&2; exit 2; }
A=$1 B=$2 ROUNDS=${3:-5} FILE=${4:-}
for build in "$A" "$B"; do
    ninja -C "$build" bench/bench_read bench/bench_traverse ${FILE:+hpfc-inspect/hpfc-inspect} >/dev/null
done
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
# tool_times BUILD SIDE: the wall seconds of hpfc-inspect --export-graph
# and --verify on FILE, as lines "SIDE TOOL SECONDS" in $OUT/tools.
tool_times() {
    inspect=$1/hpfc-inspect/hpfc-inspect
    for tool in export-graph verify; do
        start=$(date +%s.%N)
        if [ "$tool" = verify ]; then
            "$inspect" --verify "$FILE" > "$OUT/verify.$2"
        else
            "$inspect" --force --export-graph "$OUT/graph.$2.json" "$FILE" > /dev/null
        fi
        echo "$2 $tool $(date +%s.%N) $start" >> "$OUT/tools"
    done
}
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
i=0
while [ "$i" -lt "$ROUNDS" ]; do
    for side in A B; do
        eval "build=\$$side"
        "$build/bench/bench_read" | sed "s/^/$side /" >> "$OUT/read"
        for layout in paper compact; do
            "$build/bench/bench_traverse" 2 0 "$layout" | sed "s/^/$side $layout /" >> "$OUT/traverse"
        done
        [ -z "$FILE" ] || tool_times "$build" "$side"
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
        [ -z "$FILE" ] || {
            valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null \
                "$build/hpfc-inspect/hpfc-inspect" --force --export-graph "$OUT/cg.graph.json" "$FILE" \
                2> "$OUT/cg.$side.export-graph" > /dev/null
            valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null \
                "$build/hpfc-inspect/hpfc-inspect" --verify "$FILE" 2> "$OUT/cg.$side.verify" > /dev/null
        }
    done
fi
if [ -n "$FILE" ]; then
    cmp -s "$OUT/graph.A.json" "$OUT/graph.B.json" || { echo "export-graph: A and B differ" >&2; exit 1; }
    cmp -s "$OUT/verify.A" "$OUT/verify.B" || echo "verify: A and B print differently (timings?)"
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
if os.path.exists(out + "/tools"):  # "SIDE TOOL END START", seconds -> ns
    for side, tool, end, start in (line.split() for line in open(out + "/tools")):
        figures.setdefault((f"hpfc-inspect --{tool}", side), []).append((float(end) - float(start)) * 1e9)
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
    for tool in ("export-graph", "verify"):
        if os.path.exists(f"{out}/cg.A.{tool}"):
            run = {s: cachegrind_count(f"{out}/cg.{s}.{tool}") for s in "AB"}
            print(f"  hpfc-inspect --{tool:12s} {run['A']:12d} {run['B']:12d} {run['B'] / run['A']:6.3f}")
else:
    print("valgrind not installed: no instruction counts")
PY
