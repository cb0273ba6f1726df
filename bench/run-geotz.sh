#!/bin/sh
# The public time-zone map of the npm package geo-tz 8.1.9, a tiled layer:
# decoded into one layer (bench/geotz_decode.js), packed with hpfc-pack's
# defaults (--key tzid --fields all), checked against its source, and
# queried beside geo-tz's own lookup on the same random points.
#   sh bench/run-geotz.sh [N]
# N random points on the globe (default 100,000). Downloads geo-tz,
# geobuf@3 and pbf@3 (geo-tz's own decoder versions) with npm into
# build-bench/geotz/ on the first run; release build in build-bench/.
# Prints: the pack report's linking; the exported features against their
# source (every one within a band of 2e-5 degrees of its border, and the
# total symmetric difference); the answers of hpfc, shapely and geo-tz at
# the points (bench/geotz_compare.py); the per-point time and resident
# memory of hpfc's C batch (bench_locate_batch, lon/lat in, faces numbered
# once) and of geo-tz's find with its whole map cached.
set -eu
cd "$(dirname "$0")/.."
n=${1:-100000}
dir=build-bench/geotz
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
mkdir -p "$dir"
ninja -C build-bench hpfc-pack/hpfc-pack hpfc-inspect/hpfc-inspect bench/bench_locate_batch >/dev/null
if [ ! -d "$dir/node_modules/geo-tz" ]; then
    (cd "$dir" && npm init -y >/dev/null && npm install --silent geo-tz@8.1.9 geobuf@3.0.2 pbf@3.3.0)
fi
nm=$(realpath "$dir/node_modules")
[ -s "$dir/tz.geojson" ] || NODE_PATH=$nm node bench/geotz_decode.js "$nm/geo-tz/data" "$dir/tz.geojson"
build-bench/hpfc-pack/hpfc-pack --force --json --key tzid --fields all "$dir/tz.geojson" \
    -o "$dir/tz.hpfc" >"$dir/report.json"
python3 - "$dir/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
print("pack:", {k: r[k] for k in ("features_recorded", "faces", "noding", "read_seconds",
                                   "build_seconds", "write_seconds")})
print("linking:", r["linking"])
PY
build-bench/hpfc-inspect/hpfc-inspect --force --export "$dir/tz.out.geojson" "$dir/tz.hpfc"
/usr/bin/python3 tests/cli/tiled_layer.py check "$dir/tz.geojson" "$dir/tz.out.geojson" \
    "$dir/inner.txt" 2e-5 1 || echo "check: FAILED"
/usr/bin/python3 - "$dir/tz.geojson" "$dir/tz.out.geojson" <<'PY'
import json, sys
from shapely.geometry import shape
from shapely.validation import make_valid
src = json.load(open(sys.argv[1]))["features"]
out = json.load(open(sys.argv[2]))["features"]
total = sum(make_valid(shape(a["geometry"])).symmetric_difference(
    shape(b["geometry"]) if b["geometry"] else shape({"type": "Polygon", "coordinates": []})).area
    for a, b in zip(src, out))
empty = sum(1 for b in out if not b["geometry"])
print(f"symmetric difference, source against file: {total:.6f} square degrees; "
      f"{empty} features with no area")
PY
# the points: uniform on the sphere
python3 - "$n" "$dir/points.txt" "$dir/points.f64" <<'PY'
import math, random, struct, sys
n = int(sys.argv[1])
rng = random.Random(35)
lon = [rng.uniform(-180, 180) for _ in range(n)]
lat = [math.degrees(math.asin(rng.uniform(-1, 1))) for _ in range(n)]
with open(sys.argv[2], "w") as f:
    for x, y in zip(lon, lat):
        f.write(f"{x!r},{y!r}\n")
with open(sys.argv[3], "wb") as f:
    f.write(struct.pack(f"{n}d", *lon))
    f.write(struct.pack(f"{n}d", *lat))
PY
build-bench/hpfc-inspect/hpfc-inspect --locate-batch "$dir/points.txt" --lonlat "$dir/tz.hpfc" \
    >"$dir/hpfc.jsonl"
node bench/geotz_find.js "$nm" "$dir/points.f64" "$dir/geotz.jsonl" >"$dir/geotz.json"
/usr/bin/python3 bench/geotz_compare.py "$dir/tz.geojson" "$dir/points.txt" "$dir/hpfc.jsonl" \
    "$dir/geotz.jsonl"
/usr/bin/time -f '%M' -o "$dir/time.txt" build-bench/bench/bench_locate_batch locate \
    "$dir/tz.hpfc" "$dir/points.f64" lonlat 5 >"$dir/hpfc-time.json"
python3 - "$dir/hpfc-time.json" "$dir/time.txt" "$dir/geotz.json" "$n" <<'PY'
import json, sys
h = json.loads(open(sys.argv[1]).read())
rss = int(open(sys.argv[2]).read().split()[-1]) / 1024
g = json.load(open(sys.argv[3]))
n = int(sys.argv[4])
per = h["locate_best_s"] / n * 1e6
print(f"hpfc C batch: {per:.3f} us a point, {rss:.0f} MiB resident (whole process)")
print(f"geo-tz find:  {g['us_per_point']:.3f} us a point, {g['rss_mib']:.0f} MiB resident "
      f"(map cached in {g['load_seconds']:.1f} s)")
print(f"ratio: {g['us_per_point'] / per:.1f}x")
PY
