#!/bin/sh
# Issue 32's last target (bench/README.md, "One process against ogr2ogr -f
# FlatGeobuf" and "The heap kept while GDAL reads"): the one-process pack of
# a large public layer as GeoJSON against ogr2ogr -f FlatGeobuf of the same
# file, in the same run, interleaved, each with its defaults.
#   sh bench/run-gis-pack.sh [ROUNDS] [PACK]
# ROUNDS (default 3) pairs; PACK is an hpfc-pack binary (default: the
# release build in build-bench/). The layer is @geo-maps/countries-land-1m
# (213 MB, 250 features, 9.5 M points), fetched with npm into
# build-bench/scaling/ as bench/run-scaling.sh does. Prints each run's wall,
# CPU and peak (GNU time), the pack's stage seconds (--json), the medians
# and their ratio; the packs' outputs must be the same bytes.
set -eu
cd "$(dirname "$0")/.."
rounds=${1:-3}
pack=${2:-}
if [ -z "$pack" ]; then
    [ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
    ninja -C build-bench hpfc-pack/hpfc-pack >/dev/null
    pack=build-bench/hpfc-pack/hpfc-pack
fi
dir=build-bench/scaling
mkdir -p "$dir"
if [ ! -d "$dir/node_modules/@geo-maps/countries-land-1m" ]; then
    (cd "$dir" && npm init -y >/dev/null && npm install --silent @geo-maps/countries-land-1m@0.6.0)
fi
layer=$dir/node_modules/@geo-maps/countries-land-1m/map.geo.json
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
log=$work/runs
: >"$log"
for r in $(seq "$rounds"); do
    rm -f "$work/out.hpfc" "$work/out.fgb"
    /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$pack" --json "$layer" -o "$work/out.hpfc" >"$work/report.json"
    python3 - "$work/time" "$work/report.json" "$r" >>"$log" <<'EOF'
import json, sys
wall, user, sys_t, kb = open(sys.argv[1]).read().split()[-4:]
d = json.load(open(sys.argv[2]))
print("hpfc-pack %s %s %s %s read=%.1f build=%.1f write=%.1f (features %.1f)" % (
    sys.argv[3], wall, float(user) + float(sys_t), kb, d["read_seconds"], d["build_seconds"],
    d["write_seconds"], d["features_seconds"]))
EOF
    md5sum <"$work/out.hpfc" >>"$work/sums"
    # GDAL's GeoJSON reader refuses the layer's largest feature without the
    # limit lifted; hpfc-pack lifts it itself
    OGR_GEOJSON_MAX_OBJ_SIZE=0 /usr/bin/time -f "%e %U %S %M" -o "$work/time" \
        ogr2ogr -f FlatGeobuf "$work/out.fgb" "$layer"
    read -r wall user sys_t kb <"$work/time"
    echo "ogr2ogr $r $wall $(python3 -c "print($user + $sys_t)") $kb" >>"$log"
done
python3 - "$log" <<'EOF'
import statistics, sys
runs = [l.split() for l in open(sys.argv[1])]
print("%-10s %5s %9s %9s %9s  %s" % ("tool", "round", "wall_s", "cpu_s", "peak_MB", "stages"))
for r in runs:
    print("%-10s %5s %9.2f %9.2f %9.0f  %s" % (r[0], r[1], float(r[2]), float(r[3]), int(r[4]) / 1024,
                                             " ".join(r[5:])))
med = {t: statistics.median(float(r[2]) for r in runs if r[0] == t) for t in ("hpfc-pack", "ogr2ogr")}
print("median wall: hpfc-pack %.2f s, ogr2ogr -f FlatGeobuf %.2f s: %.2fx" % (
    med["hpfc-pack"], med["ogr2ogr"], med["hpfc-pack"] / med["ogr2ogr"]))
EOF
[ "$(sort -u "$work/sums" | wc -l)" = 1 ] || { echo "the packs wrote different bytes" >&2; exit 1; }
