#!/bin/sh
# hpfc-inspect --export-graph OUT FILE (interfaces §3): the JSON has the
# contract's shape and is the input's planar map (graph_check.py graph: counts,
# twin / next, genus 0, each input vertex in the box of one exported vertex of
# its degree, boxes exact decimals in the input's units, clockwise bounded
# faces); it agrees with --verify on .hpfc fixtures; OUT is written
# atomically: nothing is left behind on failure, an existing OUT is replaced
# on success and untouched on failure, and FILE cannot be its own OUT.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

gcheck() {
    python3 "$HERE/graph_check.py" "$@"
}

dir=$tmp/graphs
mkdir "$dir"

# names in $dir other than graph.json
strays() {
    for f in "$dir"/* "$dir"/.[!.]*; do
        [ -e "$f" ] && [ "$(basename "$f")" != graph.json ] && printf '%s ' "$(basename "$f")"
    done
}

# unit_exp10 of a packed file, from hpfc-inspect --json
unit_of() {
    "$INSPECT" --json "$1" | sed -n 's/.*"unit_exp10": *\(-\{0,1\}[0-9]*\).*/\1/p'
}

# export_packed PFC WHAT SIZES...
export_packed() {
    pfc=$1 what=$2
    shift 2
    "$PACK" --quiet "$@" "$pfc" -o "$tmp/g.hpfc" || { fail "pack $what"; return; }
    rm -f "$dir/graph.json"
    run "$INSPECT" --export-graph "$dir/graph.json" "$tmp/g.hpfc"
    expect_ok "export $what"
    gcheck graph "$dir/graph.json" "$pfc" "$(unit_of "$tmp/g.hpfc")" || fail "export $what"
    left=$(strays)
    [ -n "$left" ] && fail "export $what: left $left behind"
}

for pfc in "$TESTS"/data/valid/*.pfc; do
    name=$(basename "$pfc" .pfc)
    for sizes in "" "--root 3x2 --refine 3" "--root 1 --refine 2x4" "--flat"; do
        # shellcheck disable=SC2086 # $sizes holds several words
        export_packed "$pfc" "$name ${sizes:-default}" $sizes
    done
done
for pfc in "$TESTS"/../data/*.pfc; do
    [ -e "$pfc" ] || continue
    export_packed "$pfc" "$(basename "$pfc" .pfc) default"
done

# The decimals of the input, exactly: 10^-3 units, three decimals each.
"$PACK" --quiet "$TESTS/data/valid/polyline_decimals.pfc" -o "$tmp/dec.hpfc"
[ "$(unit_of "$tmp/dec.hpfc")" = "-3" ] || fail "polyline_decimals: unit_exp10 is not -3"

for f in "$TESTS"/data/valid/*.hpfc; do
    name=$(basename "$f")
    run "$INSPECT" --export-graph "$dir/graph.json" "$f"
    expect_ok "export $name"
    gcheck graph "$dir/graph.json" || fail "export $name: bad graph"
    run "$INSPECT" --verify --json "$f"
    gcheck counts "$dir/graph.json" "$tmp/out" || fail "export $name: disagrees with --verify"
done

# --json prints a summary; the text mode one line.
"$PACK" --quiet "$TESTS/data/valid/square_diagonal.pfc" -o "$tmp/sq.hpfc"
run "$INSPECT" --json --export-graph "$dir/graph.json" "$tmp/sq.hpfc"
expect_ok "export --json"
check json "$tmp/out" || fail "export --json: bad JSON"

# An existing OUT is replaced on success and untouched on failure.
echo "old" >"$dir/graph.json"
for f in "$TESTS/data/invalid/bad_pool_checksum.hpfc" \
    "$TESTS/data/invalid/corrupt_last_level_refined.hpfc" \
    "$TESTS/data/invalid/bad_magic.hpfc" "$tmp/no-such-file"; do
    name=$(basename "$f")
    run "$INSPECT" --export-graph "$dir/graph.json" "$f"
    expect_error "export $name" "hpfc-inspect: $f: " 1
    check unchanged "$dir/graph.json" "old
" || fail "export $name: touched an existing OUT"
    left=$(strays)
    [ -n "$left" ] && fail "export $name: left $left behind"
done
rm -f "$dir/graph.json"
run "$INSPECT" --export-graph "$dir/graph.json" "$TESTS/data/invalid/bad_pool_checksum.hpfc"
[ -e "$dir/graph.json" ] && fail "export of a bad file created OUT"

# A tree whose refined pixels share child images (valid checksums) is
# refused before any walk over it (paper layout: compact children are ranks).
"$PACK" --quiet --layout paper --root 1 "$TESTS/../data/delaunay-4000.pfc" -o "$tmp/deep.hpfc"
gcheck alias "$tmp/deep.hpfc" "$tmp/alias.hpfc" || fail "cannot alias images"
run "$INSPECT" --export-graph "$dir/graph.json" "$tmp/alias.hpfc"
expect_error "export aliased images" "hpfc-inspect: $tmp/alias.hpfc: " 1
[ -e "$dir/graph.json" ] && fail "export of aliased images created OUT"
echo "old" >"$dir/graph.json"
run "$INSPECT" --export-graph "$dir/graph.json" "$tmp/sq.hpfc"
expect_ok "export over an existing OUT"
gcheck graph "$dir/graph.json" "$TESTS/data/valid/square_diagonal.pfc" 0 ||
    fail "export over an existing OUT: bad graph"

# OUT in a directory that does not exist, OUT a directory, OUT = FILE.
run "$INSPECT" --export-graph "$tmp/no-such-dir/graph.json" "$tmp/sq.hpfc"
expect_error "export into a missing directory" "hpfc-inspect: " 1
run "$INSPECT" --export-graph "$dir" "$tmp/sq.hpfc"
expect_error "export onto a directory" "hpfc-inspect: " 1
for f in "$tmp"/.*.tmp "$dir"/.*.tmp; do
    [ -e "$f" ] && fail "export onto a directory: left $(basename "$f") behind"
done
cp "$tmp/sq.hpfc" "$tmp/sq-copy.hpfc"
run "$INSPECT" --export-graph "$tmp/sq.hpfc" "$tmp/sq.hpfc"
expect_error "export onto FILE" "hpfc-inspect: " 2
cmp -s "$tmp/sq.hpfc" "$tmp/sq-copy.hpfc" || fail "export onto FILE: FILE was modified"

# OUT "-": the same JSON on standard output, the summary on standard error,
# no file named "-" (from a pipe too).
had_dash=no
[ -e ./- ] && had_dash=yes
rm -f "$dir/graph.json"
run "$INSPECT" --export-graph "$dir/graph.json" "$tmp/sq.hpfc"
expect_ok "export sq to a file"
"$INSPECT" --export-graph - "$tmp/sq.hpfc" >"$tmp/stdout.json" 2>"$tmp/stderr.txt" ||
    fail "export to -: non-zero exit: $(head -c 300 "$tmp/stderr.txt")"
cmp -s "$dir/graph.json" "$tmp/stdout.json" || fail "export to -: not the file's JSON"
grep -q "vertices" "$tmp/stderr.txt" || fail "export to -: no summary on standard error"
[ $had_dash = no ] && [ -e ./- ] && fail "export to -: wrote a file named -"
"$INSPECT" --export-graph - --json - <"$tmp/sq.hpfc" >"$tmp/stdout2.json" 2>"$tmp/stderr2.txt" ||
    fail "export - to -: non-zero exit: $(head -c 300 "$tmp/stderr2.txt")"
cmp -s "$dir/graph.json" "$tmp/stdout2.json" || fail "export - to -: not the file's JSON"
python3 -c 'import json,sys; json.load(open(sys.argv[1]))' "$tmp/stderr2.txt" ||
    fail "export - to - --json: the summary is not JSON"

finish
