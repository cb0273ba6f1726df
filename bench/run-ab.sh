#!/bin/sh
# Paper against compact pool layout, the three access targets of issue #20,
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
import re, statistics, sys
out = sys.argv[1]
figures = {}  # (figure, layout) -> list of ns
def add(fig, layout, v):
    figures.setdefault((fig, layout), []).append(float(v))
for line in open(out + "/read"):
    m = re.match(r"\((b|c)\) (\w+) .*: ([\d.]+) ns each", line)
    if m:
        add({"b": "fetch + decode", "c": "locate, depth >= 16"}[m.group(1)], m.group(2), m.group(3))
# bench_traverse rows (after the layout this script prefixes): seed, edges,
# words per edge (3 columns), rPFC (3), then ns per operation: columns 9-17
# are the dart walk (none, cold, warm), the key walk (cold, warm, alone) and
# the bitmap walk (cold, warm, if); see its header.
walks = ["dart walk, no cache", "dart walk, cold cache", "dart walk, warm cache",
         "key walk, cold", "key walk, warm", "key operators alone",
         "bitmap walk, cold", "bitmap walk, warm", "bitmap walk, if"]
for line in open(out + "/traverse"):
    tok = line.replace("|", " ").split()
    if len(tok) > 17 and tok[1].isdigit() and tok[2].isdigit():
        for k, name in enumerate(walks):
            add(name, tok[0], tok[9 + k])
print(f"{'figure (ns, median of runs)':32s} {'paper':>9s} {'compact':>9s} {'ratio':>6s}  runs")
for name in ["fetch + decode", "locate, depth >= 16"] + walks:
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
import re, sys
out = sys.argv[1]
def counts(layout, r):
    text = open(f"{out}/cg.{layout}.{r}").read()
    get = lambda key: int(re.search(key + r"\s+refs:\s+([\d,]+)" if key == "I" else key + r":\s+([\d,]+)", text).group(1).replace(",", ""))
    return get("I"), get("D1  misses")
per = {}
for layout in ("paper", "compact"):
    (i0, d0), (i10, d10) = counts(layout, 0), counts(layout, 10)
    per[layout] = ((i10 - i0) / 40960, (d10 - d0) / 40960)
print("per fetch + decode (cachegrind, 40,960 fetches): instructions paper %.0f, compact %.0f (%.2fx); "
      "L1 data misses paper %.2f, compact %.2f" % (per["paper"][0], per["compact"][0],
      per["compact"][0] / per["paper"][0], per["paper"][1], per["compact"][1]))
PY
else
    echo "valgrind not installed: no instruction counts"
fi
