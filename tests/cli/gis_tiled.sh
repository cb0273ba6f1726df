#!/bin/sh
# Tiled layers (tiled_layer.py): the shipped counties and countries cut into
# quadtree cells, rectangles for the cells inside one feature and clipped
# pieces on the borders, the two cut on root boxes that differ by 0 to 10
# lattice units (exact, overlapping, slivers, mixed, duplicated features),
# as tiling tools write them. With default options but --projection none
# (so that the oracle works in the source's own units):
#  - the pack's linking finds no conflict between the walk over the faces
#    and the faces' witness points;
#  - every exported feature equals its source polygon up to a band of 1.5
#    lattice units along its border (snapping to the lattice moves a point
#    by at most sqrt(2)/2 of a unit, snap rounding a segment by as much);
#  - random points more than 3 units inside a source polygon locate to its
#    feature.
# The same tiled counties packed with all defaults (projected) locate their
# points by lon/lat. Skipped (exit 77) without GIS input or without shapely.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
GIS=$TESTS/data/gis

run "$PACK" "$GIS/ok/duplicate_borders.geojson" -o "$tmp/probe.hpfc"
if grep -q "not built in" "$tmp/err"; then
    echo "GIS input not built in: skipped"
    exit 77
fi
py=
for cand in /usr/bin/python3 python3; do
    if "$cand" -c 'import shapely' 2>/dev/null; then
        py=$cand
        break
    fi
done
if [ -z "$py" ]; then
    echo "no python3 with shapely: skipped"
    exit 77
fi

# unit_exp10 of a pack's JSON report, and 10^it
unit_of() {
    python3 -c 'import json, sys; print(10.0 ** json.load(open(sys.argv[1]))["unit_exp10"])' "$1"
}

seed=1
for src in counties_ne countries_world; do
    run "$PACK" --json --projection none "$GIS/$src.geojson" -o "$tmp/src.hpfc"
    expect_ok "$src: pack the source"
    unit=$(unit_of "$tmp/out")
    for case in "exact 5" "overlap 6" "sliver 6" "mixed+dup 7" "overlap+dup 4"; do
        variant=${case% *}
        depth=${case#* }
        what="$src $variant depth $depth"
        seed=$((seed + 1))
        "$py" "$HERE/tiled_layer.py" make "$GIS/$src.geojson" "$tmp/t.geojson" "$seed" "$unit" \
            "$depth" "$variant" >/dev/null || { fail "$what: tiled_layer.py make"; continue; }
        run "$PACK" --json --projection none "$tmp/t.geojson" -o "$tmp/t.hpfc"
        expect_ok "$what: pack"
        python3 - "$tmp/out" <<'PY' || fail "$what: the linking report"
import json, sys
r = json.load(open(sys.argv[1]))
l = r["linking"]
assert l["method"] == "topology" and l["conflicts"] == 0, l
assert r["faces_without_witness"] == 0, r["faces_without_witness"]
assert l["faces_walked"] + l["faces_anchored"] == r["faces"] - 1, (l, r["faces"])
PY
        [ "$(unit_of "$tmp/out")" = "$unit" ] || fail "$what: another lattice unit than the source's"
        run "$INSPECT" --export "$tmp/t.out.geojson" "$tmp/t.hpfc"
        expect_ok "$what: --export"
        band=$(python3 -c "print(1.5 * $unit)")
        "$py" "$HERE/tiled_layer.py" check "$tmp/t.geojson" "$tmp/t.out.geojson" "$tmp/p.txt" \
            "$band" "$seed" >"$tmp/why" 2>&1 || fail "$what: $(tail -n 3 "$tmp/why")"
        run "$INSPECT" --locate-batch "$tmp/p.txt" "$tmp/t.hpfc"
        expect_ok "$what: --locate-batch"
        "$py" "$HERE/tiled_layer.py" located "$tmp/out" "$tmp/p.txt" >"$tmp/why" 2>&1 ||
            fail "$what: $(tail -n 3 "$tmp/why")"
    done
done

# --- all defaults: projected, points by lon/lat ------------------------------
"$py" "$HERE/tiled_layer.py" make "$GIS/counties_ne.geojson" "$tmp/d.geojson" 7 \
    1e-6 6 mixed+dup >/dev/null || fail "defaults: tiled_layer.py make"
run "$PACK" --json "$tmp/d.geojson" -o "$tmp/d.hpfc"
expect_ok "defaults: pack"
python3 - "$tmp/out" <<'PY' || fail "defaults: the linking report"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["projection"] != "none" and r["linking"]["conflicts"] == 0, r["linking"]
PY
run "$INSPECT" --export "$tmp/d.out.geojson" "$tmp/d.hpfc"
expect_ok "defaults: --export"
# a band of 1e-4 degrees (about ten metres): a border point that noding put
# on a cell's side lies on the projected straight side, which bows away
# from the side straight in lon/lat by metres over a cell
"$py" "$HERE/tiled_layer.py" check "$tmp/d.geojson" "$tmp/d.out.geojson" "$tmp/dp.txt" 1e-4 7 \
    >"$tmp/why" 2>&1 || fail "defaults: $(tail -n 3 "$tmp/why")"
run "$INSPECT" --locate-batch "$tmp/dp.txt" --lonlat "$tmp/d.hpfc"
expect_ok "defaults: --locate-batch --lonlat"
"$py" "$HERE/tiled_layer.py" located "$tmp/out" "$tmp/dp.txt" >"$tmp/why" 2>&1 ||
    fail "defaults: $(tail -n 3 "$tmp/why")"

finish
