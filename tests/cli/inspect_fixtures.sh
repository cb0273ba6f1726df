#!/bin/sh
# hpfc-inspect on the .hpfc fixtures: every tests/data/valid/*.hpfc gives
# exit 0, a level table, and valid JSON with --json; every
# tests/data/invalid/*.hpfc gives the verdict of inspect_fixtures.expect:
# exit 1 with exactly one line "hpfc-inspect: FILE: <reason>" when opening
# refuses it, exit 0 when only the pools are bad (the summary never decodes
# them; --verify does, see verify.sh). A fixture missing from the list must
# not crash.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

for f in "$TESTS"/data/valid/*.hpfc; do
    [ -e "$f" ] || continue
    name=$(basename "$f")
    run "$INSPECT" "$f"
    expect_ok "$name"
    grep -q '^level' "$tmp/out" || fail "$name: no level table"
    run "$INSPECT" --json "$f"
    expect_ok "$name --json"
    check json "$tmp/out" || fail "$name: bad JSON"
done

for f in "$TESTS"/data/invalid/*.hpfc; do
    [ -e "$f" ] || continue
    name=$(basename "$f")
    line=$(awk -v n="$name" '$1 == n { sub(/^[^ ]+ +/, ""); print }' "$HERE/inspect_fixtures.expect")
    status=${line%% *}
    reason=${line#* }
    [ "$reason" = "$line" ] && reason=""
    for json in "" --json; do
        run "$INSPECT" $json "$f"
        case $status in
            0) expect_ok "$name $json" ;;
            1)
                expect_error "$name $json" "hpfc-inspect: $f: " 1
                grep -qF -- "$reason" "$tmp/err" || fail "$name: reason lacks '$reason'"
                [ -s "$tmp/out" ] && fail "$name $json: printed a summary"
                ;;
            *) [ "$rc" -le 1 ] || fail "$name $json: exit status $rc (crash?)" ;;
        esac
    done
done

# The format 1.3 fixtures (compact pool, LABL, GEOM, SHIX; the GIS one also CRS,
# FEAT, ATTR, EDGF) are hpfc-pack's own bytes: packing their sources again
# with the same options must give the same files, so a writer that changes
# the format fails here until the fixtures are regenerated with a
# spec/CHANGELOG.md entry. Every valid fixture also passes --verify and
# --export-graph (export_graph.sh) and the views (inspect_views.sh).
for spec in "two_components_hole_1_3.hpfc valid/two_components_hole.pfc" \
    "polyline_decimals_1_3.hpfc valid/polyline_decimals.pfc" \
    "borders_1_3.hpfc gis/ok/duplicate_borders.geojson --key i --fields all"; do
    set -- $spec
    name=$1 src=$2
    shift 2
    run "$PACK" -q --root 4 "$@" "$TESTS/data/$src" -o "$tmp/again.hpfc"
    if grep -q "not built in" "$tmp/err"; then
        echo "$name: GIS input not built in, not repacked"
        continue
    fi
    expect_ok "repack $name"
    cmp -s "$tmp/again.hpfc" "$TESTS/data/valid/$name" ||
        fail "$name: hpfc-pack no longer writes these bytes (regenerate the fixture)"
    run "$INSPECT" --verify "$TESTS/data/valid/$name"
    expect_ok "--verify $name"
done

finish
