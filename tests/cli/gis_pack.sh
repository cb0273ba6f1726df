#!/bin/sh
# GIS input (hpfc-pack/gis_input.c): every tests/data/gis fixture that must
# pack does, in both vertex models, with vertex / edge / face / component
# counts equal to gis_oracle.py's independent exact arrangement; the
# projection chosen and the CRS recorded are those of gis_pack.expect.
# Skipped (exit 77) when hpfc-pack was built without GIS input.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
GIS=$TESTS/data/gis

run "$PACK" "$GIS/ok/duplicate_borders.geojson" -o "$tmp/probe.hpfc"
if grep -q "not built in" "$tmp/err"; then
    echo "GIS input not built in: skipped"
    exit 77
fi

# compare REPORT ORACLE MODEL WHAT: the report's counts are the oracle's
compare() {
    python3 - "$1" "$2" "$3" <<'PY' || fail "$4: counts differ from gis_oracle.py"
import json, sys
r = json.load(open(sys.argv[1]))
o = json.load(open(sys.argv[2]))[sys.argv[3]]
bad = [f"{k} {r[k]} != {o[k]}" for k in ("vertices", "edges", "faces", "components")
       if r[k] != o[k]]
if bad:
    print("; ".join(bad))
    sys.exit(1)
PY
}

# field REPORT KEY: one field of a JSON report
field() {
    python3 -c 'import json,sys; v=json.load(open(sys.argv[1])).get(sys.argv[2]); print(v)' "$1" "$2"
}

# pack FIXTURE WANT_PROJECTION ARGS...: both vertex models against the oracle
pack() {
    f=$1
    want=$2
    shift 2
    name=$(basename "$f")
    python3 "$HERE/gis_oracle.py" "$f" >"$tmp/oracle.json" || { fail "$name: oracle failed"; return; }
    for model in all junctions; do
        run "$PACK" --json --vertices "$model" "$@" "$f" -o "$tmp/$name.hpfc"
        expect_ok "$name --vertices $model"
        [ "$rc" -eq 0 ] || continue
        cp "$tmp/out" "$tmp/report.json"
        compare "$tmp/report.json" "$tmp/oracle.json" "$model" "$name --vertices $model"
        got=$(field "$tmp/report.json" projection)
        [ "$got" = "$want" ] || fail "$name: projection $got, expected $want"
        # the CRS section holds what the report says
        run "$INSPECT" --json "$tmp/$name.hpfc"
        expect_ok "$name: hpfc-inspect"
        crs=$(field "$tmp/report.json" crs)
        [ "$(field "$tmp/out" crs)" = "$crs" ] || fail "$name: CRS section differs from the report"
        case $crs in
            +proj=*"; source "*) ;;
            *) fail "$name: CRS '$crs' is not '+proj=...; source ...'" ;;
        esac
        run "$INSPECT" --verify "$tmp/$name.hpfc"
        expect_ok "$name --vertices $model: hpfc-inspect --verify"
    done
}

while read -r fixture projection args; do
    case $fixture in '#'* | '') continue ;; esac
    # shellcheck disable=SC2086 # args are words
    pack "$GIS/$fixture" "$projection" $args
done <"$HERE/gis_pack.expect"

# several layers merged: the same layer twice stores each border once
run "$PACK" --json --invalid node --layer counties_ne --layer counties_ne \
    "$GIS/counties_ne.geojson" -o "$tmp/twice.hpfc"
expect_ok "counties_ne twice"
python3 "$HERE/gis_oracle.py" "$GIS/counties_ne.geojson" >"$tmp/oracle.json"
[ "$rc" -eq 0 ] && compare "$tmp/out" "$tmp/oracle.json" junctions "counties_ne twice" # the default model

# the antimeridian: a ring crossing it packs to the very map of the same ring
# stored cut at +-180, as Natural Earth stores its countries
for f in antimeridian_ring antimeridian_split; do
    run "$PACK" --json "$GIS/ok/$f.geojson" -o "$tmp/$f.hpfc"
    expect_ok "$f"
    run "$INSPECT" --export-graph "$tmp/$f.json" "$tmp/$f.hpfc"
    expect_ok "$f: --export-graph"
done
cmp -s "$tmp/antimeridian_ring.json" "$tmp/antimeridian_split.json" ||
    fail "antimeridian_ring and antimeridian_split export different maps"
# world-atlas's Fiji, Russia and Antarctica are the features cut
run "$PACK" --json "$GIS/countries_world.geojson" -o "$tmp/world.hpfc"
expect_ok "countries_world"
[ "$(field "$tmp/out" antimeridian_cut)" = 3 ] ||
    fail "countries_world: antimeridian_cut $(field "$tmp/out" antimeridian_cut), expected 3"

finish
