#!/bin/sh
# hpfc-pack --memory SIZE (the parts chosen for a budget): the same bytes
# as the whole build, whatever the budget; a budget the map fits in builds
# it whole, one it cannot fit in builds it in parts and says so on stderr
# (the model's estimate is larger than any budget below a few MiB, so 1M
# always takes that path, and the parts are checked against the root
# pixels the map covers); an invalid graph gives the whole build's status
# and words; the option's refusals.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

# a street grid of N x N junctions, each street with one bend, so that the
# map spans many root pixels and has interior points in them
python3 - "$tmp/grid.pfc" <<'PY'
import sys
n = 24
with open(sys.argv[1], "w") as f:
    f.write("pfc 1\n")
    for j in range(n):
        for i in range(n):
            f.write("v %d %d\n" % (100 * i, 100 * j))
    for j in range(n):
        for i in range(n):
            v = j * n + i
            if i + 1 < n:
                f.write("e %d %d %d %d\n" % (v, v + 1, 100 * i + 50, 100 * j + 7))
            if j + 1 < n:
                f.write("e %d %d %d %d\n" % (v, v + n, 100 * i + 7, 100 * j + 50))
PY

# json_field FILE KEY [SUB]: the report's value
json_field() {
    python3 -c 'import json, sys
d = json.load(open(sys.argv[1]))
for k in sys.argv[2:]:
    d = d[k]
print(d)' "$@"
}

# budgets ARGS...: packs ARGS whole, then with a budget that holds it whole
# and one that does not; compares bytes, parts and notes
budgets() {
    what=$1
    shift
    run "$PACK" -q "$@" -o "$tmp/whole.hpfc"
    expect_ok "$what (whole)"
    run "$PACK" --json --memory 1T "$@" -o "$tmp/big.hpfc"
    if [ "$rc" -ne 0 ] || [ -s "$tmp/err" ]; then
        fail "$what, 1T: exit $rc, stderr: $(head -c 300 "$tmp/err")"
    fi
    cmp -s "$tmp/whole.hpfc" "$tmp/big.hpfc" || fail "$what: --memory 1T gives other bytes"
    [ "$(json_field "$tmp/out" parts)" = 1 ] || fail "$what: --memory 1T did not build whole"
    [ "$(json_field "$tmp/out" memory budget_bytes)" = 1099511627776 ] ||
        fail "$what: the report's budget is not 1T"
    for jobs in 1 2; do
        run "$PACK" --json --memory 1M --jobs $jobs "$@" -o "$tmp/small.hpfc"
        [ "$rc" -eq 0 ] || fail "$what, 1M: exit $rc, stderr: $(head -c 300 "$tmp/err")"
        check oneline "$tmp/err" "hpfc-pack: note: --memory 1 MiB: this map needs about " >/dev/null 2>"$tmp/why" ||
            fail "$what, 1M: $(cat "$tmp/why")"
        cmp -s "$tmp/whole.hpfc" "$tmp/small.hpfc" || fail "$what: --memory 1M (--jobs $jobs) gives other bytes"
        parts=$(json_field "$tmp/out" parts)
        need=$(json_field "$tmp/out" memory estimate_bytes)
        [ "$need" -gt 1048576 ] || fail "$what: a note, but an estimate of $need bytes within 1M"
        echo "$parts" >"$tmp/parts"
    done
}

budgets "street grid" "$tmp/grid.pfc"
# the grid covers most of the 64 x 64 root pixels' map: its finest useful
# cut is more than one part
[ "$(cat "$tmp/parts")" -gt 1 ] || fail "street grid, 1M: built in $(cat "$tmp/parts") part"
budgets "street grid, 5x4 roots, paper" --root 5x4 --layout paper "$tmp/grid.pfc"
# any cut gives the same bytes (tests/cli/partitions.sh packs every
# fixture in several): here one graph fixture and two GIS layers, one of
# them noded, check the budget's path through them
budgets "two components" "$TESTS/data/valid/two_components_hole.pfc"
for layer in world lines_crossing; do
    budgets "$layer" --fields all "$TESTS/data/gis/ok/$layer.geojson"
done

# an invalid graph: hpfc_build's status and words, whatever the parts
# (partitions.sh runs every invalid fixture; these are a flaw found by a
# part (two), one by the whole graph's check, and one by the parser)
for pfc in "$TESTS"/data/invalid/nonplanar_crossing.pfc "$TESTS"/data/invalid/isolated_vertex.pfc \
    "$TESTS"/data/invalid/duplicate_point.pfc "$TESTS"/data/invalid/syntax_bad_number.pfc; do
    name=$(basename "$pfc" .pfc)
    run "$PACK" -q "$pfc" -o "$tmp/whole.hpfc"
    rc_whole=$rc
    cp "$tmp/err" "$tmp/err_whole"
    rm -f "$tmp/parts.hpfc"
    run "$PACK" -q --memory 1M "$pfc" -o "$tmp/parts.hpfc"
    grep -v "^hpfc-pack: note: --memory" "$tmp/err" >"$tmp/err_parts" || true
    [ "$rc" -eq "$rc_whole" ] || fail "$name: exit status $rc with --memory, $rc_whole whole"
    cmp -s "$tmp/err_parts" "$tmp/err_whole" || fail "$name: other words with --memory: $(cat "$tmp/err")"
    [ "$rc" -eq 0 ] || [ ! -e "$tmp/parts.hpfc" ] || fail "$name: a failed pack left an output"
done

# the option's refusals
valid=$TESTS/data/valid/loop.pfc
for bad in 0 1K 1048575 abc 4X 4GG -1G " 4G" 4G. 2000000T 18446744073709551616 ""; do
    run "$PACK" --memory "$bad" "$valid" -o "$tmp/x.hpfc"
    expect_error "--memory '$bad'" "hpfc-pack: --memory: invalid value" 2
done
for ok in 1M 1048576 2g 3GiB 5mb 1T; do
    run "$PACK" -q --memory "$ok" "$valid" -o "$tmp/ok.hpfc"
    [ "$rc" -eq 0 ] || fail "--memory $ok: exit $rc: $(head -c 200 "$tmp/err")"
done
for other in "--partitions 2" "--flat" "--partitions 2 --parts-dir $tmp"; do
    # shellcheck disable=SC2086 # the words are the options
    run "$PACK" --memory 1G $other "$valid" -o "$tmp/x.hpfc"
    expect_error "--memory with $other" "hpfc-pack: --memory: not with" 2
done
[ ! -e "$tmp/x.hpfc" ] || fail "a refused option left an output"
finish
