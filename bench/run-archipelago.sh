#!/bin/sh
# Linking at scale: hpfc-pack on the archipelago shape of
# bench/gen_archipelago.py (a coastline ring with N/2 lakes, N/2 islands in
# its bounding box, ~7 points a part) for growing N, in the default vertex
# model. One row per run: CPU time (user + system) and peak RSS of the
# whole pack (GNU time; CPU time, since the machine may be shared), wall
# time, and the stages from the --json report (wall seconds: read = GDAL,
# projection, noding and graph; build; link = numbering the faces, witness
# points, topology walk, anchors). With the pre-1.2
# witness method (--link witness) too, up to WITNESS_MAX parts.
#   sh bench/run-archipelago.sh [N ...]      (default 10000 30000 100000 300000 1000000)
# Data goes to build-bench/archipelago/ (FlatGeobuf; delete it to remake).
set -eu
cd "$(dirname "$0")/.."
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench hpfc-pack/hpfc-pack >/dev/null
dir=build-bench/archipelago
mkdir -p "$dir"
py=python3
python3 -c 'from osgeo import ogr' 2>/dev/null || py=/usr/bin/python3
WITNESS_MAX=${WITNESS_MAX:-100000}
sizes=${*:-10000 30000 100000 300000 1000000}
printf '%-8s %-9s %9s %8s %8s %8s %8s %8s %8s %8s %8s %8s\n' parts method points cpu_s wall_s \
    peak_MiB read_s build_s faces_s witn_s topo_s anch_s
for n in $sizes; do
    src=$dir/a$n.fgb
    [ -s "$src" ] || $py bench/gen_archipelago.py "$n" "$src" 2>/dev/null
    for method in topology witness; do
        [ "$method" = witness ] && [ "$n" -gt "$WITNESS_MAX" ] && continue
        /usr/bin/time -f '%e %U %S %M' -o "$dir/time.txt" \
            build-bench/hpfc-pack/hpfc-pack --link "$method" --json "$src" -o "$dir/out.hpfc" >"$dir/report.json"
        python3 - "$n" "$method" "$dir/time.txt" "$dir/report.json" <<'PY'
import json, sys
n, method, tf, rf = sys.argv[1:5]
wall, user, sys_, rss = open(tf).read().split()[-4:]
cpu = float(user) + float(sys_)
r = json.load(open(rf))
l = r["linking"]
print(f"{n:<8} {method:<9} {r['points_read']:>9} {cpu:>8.2f} {float(wall):>8.2f} {int(rss) / 1024:>8.0f} "
      f"{r['read_seconds']:>8.2f} {r['build_seconds']:>8.2f} {l['faces_seconds']:>8.2f} "
      f"{l['witness_seconds']:>8.2f} {l['topology_seconds']:>8.2f} {l['check_seconds']:>8.2f}")
PY
    done
done
