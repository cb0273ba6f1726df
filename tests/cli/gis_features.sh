#!/bin/sh
# GIS features (FEAT section, interfaces §4): the polygon features of the
# counties and the world fixtures are found again by hpfc-inspect
# --locate-batch --lonlat on random points away from borders, against an independent GDAL/GEOS answer
# (feature_oracle.py): in a private leaf exactly the features containing the
# point, in a stabbed leaf a candidate list that includes them. Also the
# single-point forms, --verify's FEAT check, and a file without features.
# Skipped (exit 77) without GIS input or without Python's GDAL bindings.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
GIS=$TESTS/data/gis
counties=$GIS/counties_ne.geojson

run "$PACK" "$GIS/ok/duplicate_borders.geojson" -o "$tmp/probe.hpfc"
if grep -q "not built in" "$tmp/err"; then
    echo "GIS input not built in: skipped"
    exit 77
fi
# The oracle needs Python's GDAL bindings (Debian: python3-gdal), which
# belong to the system interpreter.
py=
for cand in python3 /usr/bin/python3; do
    if "$cand" -c 'from osgeo import ogr' 2>/dev/null; then
        py=$cand
        break
    fi
done
if [ -z "$py" ]; then
    echo "no python3 with osgeo (python3-gdal): skipped"
    exit 77
fi

run "$PACK" --json --invalid node --key name "$counties" -o "$tmp/c.hpfc"
expect_ok "pack --key name"
python3 - "$tmp/out" <<'PY' || fail "pack report: features"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["polygon_features"] == 54, r["polygon_features"]
assert r["key_field"] == "name", r["key_field"]
assert r["faces_with_features"] == r["faces"] - 1, (r["faces_with_features"], r["faces"])
assert r["faces_without_witness"] == 0, r["faces_without_witness"]
PY

run "$INSPECT" --verify "$tmp/c.hpfc"
expect_ok "--verify with FEAT"
grep -q "features        FEAT section: ok" "$tmp/out" || fail "--verify does not check FEAT"

# compare LAYER FILE WHAT: --locate-batch --lonlat against feature_oracle.py
compare() {
    "$py" "$HERE/feature_oracle.py" "$1" name 7 400 "$tmp/points.txt" "$tmp/expected.json" ||
        fail "$3: feature_oracle.py failed"
    run "$INSPECT" --locate-batch "$tmp/points.txt" --lonlat "$2"
    expect_ok "$3: --locate-batch --lonlat"
    python3 - "$tmp/out" "$tmp/expected.json" <<'PY' || fail "$3: --locate-batch disagrees with GDAL/GEOS"
import json, sys
answers = [json.loads(line) for line in open(sys.argv[1])]
expected = json.load(open(sys.argv[2]))
assert len(answers) == len(expected), (len(answers), len(expected))
private = exact = covered = 0
for k, (a, want) in enumerate(zip(answers, expected)):
    got = sorted(({"fid": f["fid"], "key": f["key"]} for f in a["features"]),
                 key=lambda d: d["fid"])
    assert a["inside"], f"point {k} outside the domain"
    # the points lie 2 km from every border: never on one
    assert not a.get("on_boundary"), a
    if a.get("exact") or a["private"]:
        exact += bool(a.get("exact"))
        private += bool(a["private"])
        assert len(a["faces"]) == 1, a
        assert got == want, f"point {k} ({a['lon']}, {a['lat']}): got {got}, want {want}"
    else:
        assert all(w in got for w in want), f"point {k}: {want} not among {got}"
    covered += bool(want)
# the test means something only if many answers are single faces (every one
# with exact geometry, the default) and most points fall in some feature
assert exact + private >= len(answers) // 4, f"only {exact} exact and {private} private answers"
assert covered >= len(answers) // 2, f"only {covered} points in a feature"
print(f"{len(answers)} points, {exact} exact, {private} private, {covered} in a feature")
PY
}

compare "$counties" "$tmp/c.hpfc" counties
world=$GIS/countries_world.geojson
run "$PACK" --key name "$world" -o "$tmp/w.hpfc"
expect_ok "pack the world --key name"
compare "$world" "$tmp/w.hpfc" world
# the counties' points again: the single-point checks below use them
compare "$counties" "$tmp/c.hpfc" counties

# the single-point forms agree with the batch
first=$(head -1 "$tmp/points.txt")
run "$INSPECT" --locate-lonlat "$first" --json "$tmp/c.hpfc"
expect_ok "--locate-lonlat"
head -1 "$tmp/out" >"$tmp/one.json"
run "$INSPECT" --locate-batch - --lonlat "$tmp/c.hpfc"
"$INSPECT" --locate-batch - --lonlat "$tmp/c.hpfc" <"$tmp/points.txt" | head -1 >"$tmp/batch1.json"
python3 - "$tmp/one.json" "$tmp/batch1.json" <<'PY' || fail "--locate-lonlat and --locate-batch differ"
import json, sys
one, row = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
assert row.pop("line") == 1 and row.pop("id") is None, row  # batch rows add these (interfaces §4)
assert one == row, (one, row)
PY
x=$(python3 -c 'import json,sys; a=json.load(open(sys.argv[1])); print(repr(a["x"]) + "," + repr(a["y"]))' "$tmp/one.json")
run "$INSPECT" --locate "$x" --json "$tmp/c.hpfc"
expect_ok "--locate X,Y"
python3 - "$tmp/out" "$tmp/one.json" <<'PY' || fail "--locate X,Y and --locate-lonlat differ"
import json, sys
a, b = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
assert a["faces"] == b["faces"] and a["features"] == b["features"], (a, b)
PY

# a malformed line is an error row naming its line, and the run goes on
printf '%s\nnot a point\n%s\n' "$first" "$first" >"$tmp/bad.txt"
run "$INSPECT" --locate-batch "$tmp/bad.txt" --lonlat "$tmp/c.hpfc"
expect_ok "--locate-batch bad line"
python3 - "$tmp/out" <<'PY' || fail "--locate-batch bad line: not an error row between two answers"
import json, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
assert [r["line"] for r in rows] == [1, 2, 3], rows
assert "error" in rows[1] and "faces" not in rows[1], rows[1]
assert rows[0]["features"] == rows[2]["features"] and "error" not in rows[2], rows
PY

# without --key: features without keys; a .pfc file has no FEAT at all
run "$PACK" --invalid node "$counties" -o "$tmp/nokey.hpfc"
run "$INSPECT" --locate-lonlat "$first" --json "$tmp/nokey.hpfc"
python3 -c 'import json,sys; a=json.load(open(sys.argv[1])); assert a["features"] and all("key" not in f for f in a["features"]), a' \
    "$tmp/out" || fail "features without --key carry a key"
run "$PACK" "$TESTS/data/valid/square_diagonal.pfc" -o "$tmp/plain.hpfc"
run "$INSPECT" --locate 1,1 --json "$tmp/plain.hpfc"
python3 -c 'import json,sys; a=json.load(open(sys.argv[1])); assert a["features"] == [], a' \
    "$tmp/out" || fail "a .pfc file reports features"
run "$PACK" --key nosuchfield "$counties" --invalid node -o "$tmp/nofield.hpfc"
expect_error "--key unknown field" "hpfc-pack: $counties: --key nosuchfield: layer" 1
[ -e "$tmp/nofield.hpfc" ] && fail "--key unknown field left an output"

finish
