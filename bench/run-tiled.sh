#!/bin/sh
# Tiled versions of two public layers, checked as tests/cli/gis_tiled.sh
# checks the shipped samples: us-atlas counties-10m and world-atlas
# countries-10m (npm, fetched into build-bench/atlas/ on the first run) cut
# into quadtree cells by tests/cli/tiled_layer.py (rectangles and clipped
# pieces on root boxes a few lattice units apart, one variant a layer),
# packed with --projection none, every feature compared with its source
# and random inner points located.
#   sh bench/run-tiled.sh [DEPTH]      (default 7)
set -eu
cd "$(dirname "$0")/.."
depth=${1:-7}
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench hpfc-pack/hpfc-pack hpfc-inspect/hpfc-inspect >/dev/null
dir=build-bench/atlas
mkdir -p "$dir"
if [ ! -d "$dir/node_modules/us-atlas" ]; then
    (cd "$dir" && npm init -y >/dev/null && npm install --silent us-atlas@3 world-atlas@2)
fi
[ -s "$dir/counties.geojson" ] || ogr2ogr -f GeoJSON "$dir/counties.geojson" \
    "$dir/node_modules/us-atlas/counties-10m.json" counties
[ -s "$dir/countries.geojson" ] || ogr2ogr -f GeoJSON "$dir/countries.geojson" \
    "$dir/node_modules/world-atlas/countries-10m.json" countries
pack=build-bench/hpfc-pack/hpfc-pack
inspect=build-bench/hpfc-inspect/hpfc-inspect
for case in "counties mixed+dup" "countries overlap"; do
    name=${case% *}
    variant=${case#* }
    $pack --force --json --projection none "$dir/$name.geojson" -o "$dir/$name.hpfc" >"$dir/r.json"
    unit=$(python3 -c 'import json, sys; print(10.0 ** json.load(open(sys.argv[1]))["unit_exp10"])' \
        "$dir/r.json")
    t=$dir/$name.tiled
    /usr/bin/python3 tests/cli/tiled_layer.py make "$dir/$name.geojson" "$t.geojson" 3 "$unit" \
        "$depth" "$variant"
    /usr/bin/time -f '%e s, %M KiB' -o "$dir/time.txt" \
        $pack --force --json --projection none "$t.geojson" -o "$t.hpfc" >"$dir/r.json"
    python3 - "$dir/r.json" "$dir/time.txt" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
print("  pack:", open(sys.argv[2]).read().split("\n")[0], "features", r["features_recorded"],
      "faces", r["faces"], "noding", r["noding"], "linking", r["linking"])
PY
    $inspect --force --export "$t.out.geojson" "$t.hpfc" >/dev/null
    /usr/bin/python3 tests/cli/tiled_layer.py check "$t.geojson" "$t.out.geojson" "$t.points" \
        "$(python3 -c "print(1.5 * $unit)")" 3
    $inspect --locate-batch "$t.points" "$t.hpfc" >"$t.answers"
    /usr/bin/python3 tests/cli/tiled_layer.py located "$t.answers" "$t.points"
done
