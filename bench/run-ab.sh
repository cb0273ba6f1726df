#!/bin/sh
# Paper against compact pool layout, the three access targets of the compact layout,
# in one run (the machine's speed drifts; ratios taken in the same run do
# not):
#   fetch + decode of a random leaf   compact at most 2x paper
#   locate at depth 16                compact at most 1.5x paper
#   traversal walks                   compact at most 1.5x paper
# bench_read and bench_traverse run ROUNDS times each, layouts alternated;
# the script prints the median of each figure per layout and their ratio.
# With valgrind installed it also counts the instructions of one fetch +
# decode (cachegrind, 10 rounds of 4096 fetches minus 0 rounds), a figure
# that does not depend on the machine's load.
#
# usage: sh bench/run-ab.sh [ROUNDS]      (default 7; from the repository top)
set -eu
ROUNDS=${1:-7}
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench bench/bench_read bench/bench_traverse >/dev/null
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
i=0
while [ "$i" -lt "$ROUNDS" ]; do
    build-bench/bench/bench_read >> "$OUT/read"
    for layout in paper compact; do
        build-bench/bench/bench_traverse 2 0 "$layout" | sed "s/^/$layout /" >> "$OUT/traverse"
    done
    i=$((i + 1))
done
echo "load after:  $(cut -d' ' -f1-3 /proc/loadavg)"
python3 - "$OUT" <<'PY'
import statistics, sys
sys.path.insert(0, "bench")
from ab_figures import WALKS, read_figures, traverse_figures
out = sys.argv[1]
figures = {}  # (figure, layout) -> list of ns
for _, name, layout, ns in read_figures(out + "/read"):
    figures.setdefault((name, layout), []).append(ns)
for (layout,), name, ns in traverse_figures(out + "/traverse", prefixed=1):
    figures.setdefault((name, layout), []).append(ns)
print(f"{'figure (ns, median of runs)':32s} {'paper':>9s} {'compact':>9s} {'ratio':>6s}  runs")
for name in ["fetch + decode", "locate, depth >= 16"] + WALKS:
    p, c = figures.get((name, "paper")), figures.get((name, "compact"))
    if p and c:
        mp, mc = statistics.median(p), statistics.median(c)
        print(f"{name:32s} {mp:9.1f} {mc:9.1f} {mc / mp:6.2f}  {len(p)}")
PY
if command -v valgrind >/dev/null 2>&1; then
    for layout in paper compact; do
        for r in 0 10; do
            valgrind --tool=cachegrind --cache-sim=yes --cachegrind-out-file=/dev/null \
                build-bench/bench/bench_read fetch "$layout" "$r" 2> "$OUT/cg.$layout.$r" > /dev/null
        done
    done
    python3 - "$OUT" <<'PY'
import sys
sys.path.insert(0, "bench")
from ab_figures import FETCHES_PER_10_ROUNDS as N, cachegrind_count
out = sys.argv[1]
per = {}
for layout in ("paper", "compact"):
    counts = {r: (cachegrind_count(f"{out}/cg.{layout}.{r}"),
                  cachegrind_count(f"{out}/cg.{layout}.{r}", "D1  misses")) for r in (0, 10)}
    per[layout] = ((counts[10][0] - counts[0][0]) / N, (counts[10][1] - counts[0][1]) / N)
print("per fetch + decode (cachegrind, 40,960 fetches): instructions paper %.0f, compact %.0f (%.2fx); "
      "L1 data misses paper %.2f, compact %.2f" % (per["paper"][0], per["compact"][0],
      per["compact"][0] / per["paper"][0], per["paper"][1], per["compact"][1]))
PY
else
    echo "valgrind not installed: no instruction counts"
fi
