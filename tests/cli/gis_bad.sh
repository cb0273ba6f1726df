#!/bin/sh
# Bad GIS input: every tests/data/gis/bad fixture, and the command lines of
# gis_bad.expect, fail with exit 1 (2 for usage errors), exactly one stderr
# line containing the expected words, no report and no file left behind.
# Skipped (exit 77) when hpfc-pack was built without GIS input.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
GIS=$TESTS/data/gis

run "$PACK" "$GIS/ok/duplicate_borders.geojson" -o "$tmp/probe.hpfc"
if grep -q "not built in" "$tmp/err"; then
    echo "GIS input not built in: skipped"
    exit 77
fi
rm -f "$tmp/probe.hpfc"
dir=$tmp/outdir
mkdir "$dir"

seen=""
while read -r status fixture want; do
    case $status in '#'* | '') continue ;; esac
    # fixture: NAME or NAME|ARG|ARG...
    args=$(printf '%s' "$fixture" | cut -s -d'|' -f2- | tr '|' ' ')
    file=$(printf '%s' "$fixture" | cut -d'|' -f1)
    seen="$seen $file"
    # shellcheck disable=SC2086 # args are words
    run "$PACK" --json $args "$GIS/$file" -o "$dir/out.hpfc"
    expect_error "$fixture" "hpfc-pack: " "$status"
    [ -s "$tmp/out" ] && fail "$fixture: printed a report"
    [ -n "$(ls -A "$dir")" ] && fail "$fixture: left $(ls -A "$dir") behind"
    grep -qF -- "$want" "$tmp/err" || fail "$fixture: reason lacks '$want': $(cat "$tmp/err")"
    rm -f "$dir"/* "$dir"/.[!.]* 2>/dev/null
done <"$HERE/gis_bad.expect"

# every fixture of bad/ is listed
for f in "$GIS"/bad/*; do
    case " $seen " in *" bad/$(basename "$f") "*) ;; *) fail "bad/$(basename "$f") not in gis_bad.expect" ;; esac
done

finish
