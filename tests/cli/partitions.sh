#!/bin/sh
# hpfc-pack --partitions N (a build in parts, one after another or --jobs
# at a time in threads, joined):
# the same bytes as the single build for every valid .pfc and GIS fixture,
# under several image sizes, both layouts and both vertex models; the
# same exit status and message for every invalid .pfc; the option's own
# refusals. GIS layers noded `partial` or `all` included (noding comes
# before the parts).
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

# same_bytes WHAT ARGS...: packs with ARGS once whole and once in 2, 7 and
# 5000 parts (more than root pixels: one a pixel), then 7 parts on 3
# threads and --jobs 2 alone (2 parts, 2 threads), and compares.
same_bytes() {
    what=$1
    shift
    run "$PACK" -q "$@" -o "$tmp/whole.hpfc"
    expect_ok "$what (whole)"
    for k in 2 7 5000 "7 --jobs 3"; do
        # shellcheck disable=SC2086 # k may carry --jobs
        run "$PACK" -q --partitions $k "$@" -o "$tmp/parts.hpfc"
        expect_ok "$what ($k parts)"
        cmp -s "$tmp/whole.hpfc" "$tmp/parts.hpfc" || fail "$what: $k parts give other bytes"
    done
    run "$PACK" -q --jobs 2 "$@" -o "$tmp/parts.hpfc"
    expect_ok "$what (--jobs 2)"
    cmp -s "$tmp/whole.hpfc" "$tmp/parts.hpfc" || fail "$what: --jobs 2 gives other bytes"
}

for pfc in "$TESTS"/data/valid/*.pfc; do
    name=$(basename "$pfc" .pfc)
    same_bytes "$name" "$pfc"
    same_bytes "$name 3x2/3 paper" --root 3x2 --refine 3 --layout paper "$pfc"
    same_bytes "$name 1/2x4 leaf 1" --root 1 --refine 2x4 --leaf-points 1 "$pfc"
done

nodings=""
for gis in "$TESTS"/data/gis/ok/*.geojson "$TESTS"/data/gis/*.geojson; do
    name=$(basename "$gis" .geojson)
    same_bytes "$name" --fields all "$gis"
    same_bytes "$name vertices all 5x4" --fields all --vertices all --root 5x4 "$gis"
    run "$PACK" --json "$gis" -o "$tmp/whole.hpfc"
    nodings="$nodings $(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["noding"])' "$tmp/out" 2>/dev/null)"
done
case $nodings in
    *partial* | *all*) ;;
    *) fail "no GIS fixture was noded (nodings:$nodings): the noded path is untested" ;;
esac

# an invalid graph: hpfc_build's status and words, whatever the parts
for pfc in "$TESTS"/data/invalid/*.pfc; do
    name=$(basename "$pfc" .pfc)
    run "$PACK" -q "$pfc" -o "$tmp/whole.hpfc"
    rc_whole=$rc
    cp "$tmp/err" "$tmp/err_whole"
    for jobs in 1 3; do
        rm -f "$tmp/parts.hpfc"
        run "$PACK" -q --partitions 4 --jobs $jobs "$pfc" -o "$tmp/parts.hpfc"
        [ "$rc" -eq "$rc_whole" ] || fail "$name: exit status $rc in parts ($jobs at once), $rc_whole whole"
        cmp -s "$tmp/err" "$tmp/err_whole" || fail "$name: other words in parts ($jobs at once): $(cat "$tmp/err")"
        [ "$rc" -eq 0 ] || [ ! -e "$tmp/parts.hpfc" ] || fail "$name: a failed pack left an output"
    done
done

# the option's refusals
valid=$TESTS/data/valid/loop.pfc
for bad in 0 -1 x 2x; do
    run "$PACK" --partitions "$bad" "$valid" -o "$tmp/x.hpfc"
    expect_error "--partitions $bad" "hpfc-pack: " 2
done
run "$PACK" --partitions 2 --flat "$valid" -o "$tmp/x.hpfc"
expect_error "--partitions with --flat" "hpfc-pack: " 2
for bad in 0 -1 x 1025; do
    run "$PACK" --jobs "$bad" "$valid" -o "$tmp/x.hpfc"
    expect_error "--jobs $bad" "hpfc-pack: --jobs: invalid value" 2
done
run "$PACK" -j 2 --flat "$valid" -o "$tmp/x.hpfc"
expect_error "--jobs with --flat" "hpfc-pack: --jobs: not with --flat" 2
run "$PACK" --partitions 2 --jobs 2 --parts-dir "$tmp" "$valid" -o "$tmp/x.hpfc"
expect_error "--jobs with --parts-dir" "hpfc-pack: --jobs: not with" 2
[ ! -e "$tmp/x.hpfc" ] || fail "a refused option left an output"

# --parts-dir (the parts built by others; python/tests/test_pack.py drives
# the whole protocol): its refusals, and a plan line before standard input
# says the parts are not there
mkdir "$tmp/parts"
for args in "--parts-dir $tmp/parts" "--partitions 2 --parts-dir $tmp/parts --flat" \
    "--partitions 2 --parts-dir"; do
    # shellcheck disable=SC2086 # the words are the options
    run "$PACK" $args "$valid" -o "$tmp/x.hpfc"
    expect_error "$args" "hpfc-pack: " 2
done
run "$PACK" --partitions 2 --parts-dir "$tmp/parts" "$valid" -o -
expect_error "--parts-dir with -o -" "hpfc-pack: " 2
run "$PACK" --partitions 3 --parts-dir "$tmp/parts" "$valid" -o "$tmp/x.hpfc"
expect_error "--parts-dir, no answer" "hpfc-pack: $valid: standard input ended before the parts were built" 1
[ ! -e "$tmp/x.hpfc" ] || fail "--parts-dir, no answer: an output was written"
python3 -c 'import json, sys; p = json.loads(open(sys.argv[1]).readline()); assert p["parts"] == 3, p' "$tmp/out" ||
    fail "--parts-dir: no plan line on standard output: $(head -c 200 "$tmp/out")"
[ -s "$tmp/parts/part-0.pfc" ] && [ -e "$tmp/parts/part-2.ids" ] || fail "--parts-dir: the parts' graphs were not cut"
run "$PACK" --partitions 3 --parts-dir "$tmp/no/such/dir" "$valid" -o "$tmp/x.hpfc"
expect_error "--parts-dir, no such directory" "hpfc-pack: " 1
finish
