#!/bin/sh
# Every tests/data/valid/*.pfc packs (exit 0, nothing on stderr), with the
# default sizes and odd ones; the --json report parses, counts the .pfc's
# vertices and edges and adds up; the text report is printed by default;
# hpfc-inspect --json on the output agrees with the report level by level.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

for pfc in "$TESTS"/data/valid/*.pfc; do
    name=$(basename "$pfc" .pfc)
    for sizes in "" "--root 3x2 --refine 3" "--root 1 --refine 2x4" "--flat"; do
        what="$name ${sizes:-default}"
        out="$tmp/$name.hpfc"
        # shellcheck disable=SC2086 # $sizes holds several words
        run "$PACK" $sizes --json "$pfc" -o "$out"
        expect_ok "pack $what"
        [ -f "$out" ] || { fail "pack $what: no output file"; continue; }
        check report "$tmp/out" "$pfc" || fail "pack $what: bad report"
        cp "$tmp/out" "$tmp/report.json"
        run "$INSPECT" --json "$out"
        expect_ok "inspect $what"
        check agree "$tmp/report.json" "$tmp/out" || fail "inspect $what disagrees"
        run "$INSPECT" "$out"
        expect_ok "inspect (text) $what"
        grep -q '^level' "$tmp/out" || fail "inspect (text) $what: no level table"
        rm -f "$out"
    done
    run "$PACK" "$pfc" -o "$tmp/$name.hpfc"
    expect_ok "pack (text) $name"
    grep -q 'vertices' "$tmp/out" || fail "pack (text) $name: no report"
    run "$PACK" --quiet "$pfc" -o "$tmp/$name.hpfc"
    expect_ok "pack --quiet $name"
    [ -s "$tmp/out" ] && fail "pack --quiet $name: printed a report"
done

# An existing OUTPUT is replaced on success.
echo "old" >"$tmp/replace.hpfc"
run "$PACK" --quiet "$TESTS/data/valid/loop.pfc" -o "$tmp/replace.hpfc"
expect_ok "pack over an existing file"
run "$INSPECT" "$tmp/replace.hpfc"
expect_ok "inspect the replaced file"

# Content detection: a .pfc without the suffix.
cp "$TESTS/data/valid/loop.pfc" "$tmp/loop.txt"
run "$PACK" --quiet "$tmp/loop.txt" -o "$tmp/loop.hpfc"
expect_ok "pack a .pfc named .txt"

# File names that JSON must escape (quote, backslash, tab, a byte that is
# not UTF-8) still give valid JSON, and an error about them stays one line.
odd=$(printf 'we"ird\\na\tme\351')
cp "$TESTS/data/valid/loop.pfc" "$tmp/$odd.pfc"
run "$PACK" --json "$tmp/$odd.pfc" -o "$tmp/$odd.hpfc"
expect_ok "pack an oddly named file"
check json "$tmp/out" || fail "pack an oddly named file: bad JSON"
run "$INSPECT" --json "$tmp/$odd.hpfc"
expect_ok "inspect an oddly named file"
check json "$tmp/out" || fail "inspect an oddly named file: bad JSON"
nl=$(printf 'new\nline')
run "$PACK" "$tmp/$nl.pfc" -o "$tmp/x.hpfc"
expect_error "pack a missing file with a newline in its name" "hpfc-pack: " 1

finish
