#!/bin/sh
# One answer from a cold handle: bench_cold (hpfc_open + one
# point location + the point's faces and features + hpfc_close, median of
# 100 fresh opens) and the hpfc-inspect --locate* process against
# hpfc-inspect --version, on three files from about 1 MB to several hundred
# MB, each packed with its LABL section (the default) and, for the two
# smaller ones, without (--no-labels: the answer numbers the faces first).
#   sh bench/run-cold.sh
# Data: US counties (npm us-atlas, counties-10m.json, into build-bench/npm/)
# and two synthetic continental coverages (bench/gen_continent.py, into
# build-bench/gis/, shared with run-gis.sh).
set -eu
cd "$(dirname "$0")/.."
[ -f build-bench/build.ninja ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench bench/bench_cold hpfc-pack/hpfc-pack hpfc-inspect/hpfc-inspect >/dev/null
PACK=build-bench/hpfc-pack/hpfc-pack
INSPECT=build-bench/hpfc-inspect/hpfc-inspect
COLD=build-bench/bench/bench_cold
dir=build-bench/cold
mkdir -p "$dir" build-bench/gis build-bench/npm

counties=build-bench/npm/node_modules/us-atlas/counties-10m.json
if [ ! -s "$counties" ]; then
    (cd build-bench/npm && npm install --silent us-atlas >/dev/null)
fi
for spec in "continent-20x12x250:20 12 250" "continent:"; do
    name=${spec%%:*}
    src=build-bench/gis/$name.geojson
    if [ ! -s "$src" ]; then
        # shellcheck disable=SC2086 # the size is three words or none
        python3 bench/gen_continent.py "$src.tmp" ${spec#*:} && mv "$src.tmp" "$src"
    fi
done

# pack NAME VARIANTS SOURCE OPTIONS...: NAME.hpfc (labels) and/or
# NAME-nolabels.hpfc, with the pack's wall time
pack() {
    name=$1 variants=$2 src=$3
    shift 3
    for variant in $variants; do
        out=$dir/$name.hpfc extra=""
        if [ "$variant" = nolabels ]; then
            out=$dir/$name-nolabels.hpfc extra=--no-labels
        fi
        if [ ! -s "$out" ]; then
            t0=$(date +%s.%N)
            # shellcheck disable=SC2086 # $extra is one word or none
            "$PACK" --quiet "$@" $extra "$src" -o "$out"
            t1=$(date +%s.%N)
            echo "pack $out: $(awk "BEGIN { printf \"%.1f\", $t1 - $t0 }") s"
        fi
    done
}
pack counties "labels nolabels" "$counties" --invalid node --layer counties --key name
pack continent-small "labels nolabels" build-bench/gis/continent-20x12x250.geojson --key name
pack continent "labels nolabels" build-bench/gis/continent.geojson --key name
# several hundred MB: a 2600 x 2600 jittered grid mesh (20 M edges, about 370 MB
# with LABL; 1.6 GB and about a minute of CPU to pack), labels only
ninja -C build-bench tests/gen-pfc >/dev/null
[ -s "$dir/grid2600.pfc" ] || build-bench/tests/gen-pfc grid 1 2600 "$dir/grid2600.pfc"
pack grid2600 labels "$dir/grid2600.pfc"

echo
echo "section sizes (bits per edge: LABL beside POOL)"
for f in "$dir/counties.hpfc" "$dir/continent-small.hpfc" "$dir/continent.hpfc" \
    "$dir/grid2600.hpfc"; do
    "$INSPECT" --sections --json "$f" | python3 -c '
import json, sys
d = json.load(sys.stdin)
s = {x["tag"]: x["length"] for x in d["sections"]}
print(sys.argv[1], " ".join(f"{t.strip()} {8 * n:,} bits" for t, n in s.items()))' "$f"
done

echo
echo "(a) one answer from a fresh open: bench_cold FILE 100 (microseconds)"
for f in "$dir/counties.hpfc" "$dir/continent-small.hpfc" "$dir/continent.hpfc" \
    "$dir/grid2600.hpfc"; do
    $COLD "$f" 100
done
echo "    the same without LABL (each answer numbers the map's faces: 10 opens, 3 on the largest)"
$COLD "$dir/counties-nolabels.hpfc" 10
$COLD "$dir/continent-small-nolabels.hpfc" 10
$COLD "$dir/continent-nolabels.hpfc" 3

echo
echo "(b) the hpfc-inspect process: --locate (counties: lattice in degrees; the continents:"
echo "    --locate-lonlat) against --version: median CPU time (user + system) and wall time"
echo "    of 30 runs (3 without LABL), milliseconds"
python3 - "$INSPECT" "$dir" <<'PY'
import os, statistics, subprocess, sys, time
inspect, d = sys.argv[1], sys.argv[2]
def run(args):
    t0 = time.perf_counter()
    p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, _, ru = os.wait4(p.pid, 0)
    return (ru.ru_utime + ru.ru_stime) * 1e3, (time.perf_counter() - t0) * 1e3
def medians(args, n):
    r = [run(args) for _ in range(n)]
    return statistics.median(c for c, _ in r), statistics.median(w for _, w in r)
cases = [("counties", ["--locate", "-77.03,38.9"]),
         ("continent-small", ["--locate-lonlat", "-100.5,37.2"]),
         ("continent", ["--locate-lonlat", "-100.5,37.2"]),
         ("grid2600", ["--locate", "16000.5,16000.5"])]
print(f"{'file':<26} {'--version cpu':>14} {'--locate cpu':>13} {'diff cpu':>9} | "
      f"{'--version wall':>14} {'--locate wall':>13} {'diff wall':>9}")
for name, q in cases:
    for suffix in ("", "-nolabels"):
        f = f"{d}/{name}{suffix}.hpfc"
        if not os.path.exists(f):
            continue
        n = 30 if not suffix else 3
        vc, vw = medians([inspect, "--version"], n)
        lc, lw = medians([inspect] + q + [f], n)
        print(f"{name + suffix:<26} {vc:14.2f} {lc:13.2f} {lc - vc:9.2f} | "
              f"{vw:14.2f} {lw:13.2f} {lw - vw:9.2f}")
PY
