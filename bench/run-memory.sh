#!/bin/sh
# hpfc-pack --memory SIZE (bench/README.md, "A memory budget"): packs a
# generated street network (bench/gen_streets.py) whole, then under each
# budget, and gives the parts chosen, the model's estimate, the process's
# own memory at its peak (RssAnon of /proc/PID/status, sampled every 3 ms:
# a lower bound, as polling can miss a short rise; the input .pfc is mapped
# and not counted) and the wall time; the files are compared byte for byte.
#   sh bench/run-memory.sh [POINTS [BUDGET ...]]
# default: 1e7 and 200M 260M 300M 400M 460M 600M. Release build in
# build-bench/; the network is generated once into build-bench/streets/.
set -eu
cd "$(dirname "$0")/.."
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench hpfc-pack/hpfc-pack >/dev/null
pack=build-bench/hpfc-pack/hpfc-pack
dir=build-bench/streets
mkdir -p "$dir"
n=${1:-1e7}
[ $# -gt 0 ] && shift
budgets=${*:-200M 260M 300M 400M 460M 600M}
pfc=$dir/streets-$n.pfc
[ -f "$pfc" ] || python3 bench/gen_streets.py "$n" "$pfc"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# run OUT ARGS...: packs, prints "parts estimate_MiB own_peak_MiB wall_s"
run() {
    out=$1
    shift
    python3 - "$pack" --json --force "$@" "$pfc" -o "$out" <<'PY'
import json, subprocess, sys, time

def anon(pid):
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith("RssAnon:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0

t0 = time.time()
p = subprocess.Popen(sys.argv[1:], stdout=subprocess.PIPE, text=True)
peak = 0
while p.poll() is None:
    peak = max(peak, anon(p.pid))
    time.sleep(0.003)
wall = time.time() - t0
report = json.loads(p.stdout.read())
need = report.get("memory", {}).get("estimate_bytes", 0)
print(report["parts"], "%.0f" % (need / 2**20), "%.0f" % (peak / 1024), "%.2f" % wall)
PY
}
printf '%-8s %8s %6s %13s %13s %8s  %s\n' points budget parts estimate_MiB own_peak_MiB wall_s bytes
# shellcheck disable=SC2046 # the four fields, split on purpose
set -- $(run "$work/whole.hpfc")
printf '%-8s %8s %6s %13s %13s %8s  %s\n' "$n" none "$1" - "$3" "$4" ""
for b in $budgets; do
    # shellcheck disable=SC2046
    set -- $(run "$work/budget.hpfc" --memory "$b")
    same=same
    cmp -s "$work/whole.hpfc" "$work/budget.hpfc" || same=DIFFERENT
    printf '%-8s %8s %6s %13s %13s %8s  %s\n' "$n" "$b" "$1" "$2" "$3" "$4" "$same"
done
