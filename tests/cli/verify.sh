#!/bin/sh
# hpfc-inspect --verify (interfaces §3): exit 0 and a report with the input's
# counts on files packed from every tests/data/valid/*.pfc and data/*.pfc and
# on every tests/data/valid/*.hpfc; exit 1 with exactly one stderr line
# "hpfc-inspect: FILE: <problem>" on every tests/data/invalid/*.hpfc and on
# packed files with a flipped pool bit, whether or not the checksums are then
# fixed up (the structural checks must catch, or at least survive, the flip).
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

gcheck() {
    python3 "$HERE/graph_check.py" "$@"
}

# expect_one_line WHAT PREFIX: lib.sh's expect_error with status 1, in shell
# only: the loops below run it too often to start python3 each time.
expect_one_line() {
    if [ "$rc" -ne 1 ]; then
        fail "$1: exit status $rc, expected 1 (stderr: $(head -c 300 "$tmp/err"))"
    elif [ "$(wc -l <"$tmp/err")" -ne 1 ] || [ -n "$(tail -c 1 "$tmp/err")" ]; then
        fail "$1: stderr is not exactly one line: $(head -c 300 "$tmp/err")"
    else
        case $(cat "$tmp/err") in
            "$2"*) ;;
            *) fail "$1: stderr does not start with '$2': $(cat "$tmp/err")" ;;
        esac
    fi
}

# verify_packed PFC WHAT SIZES...: pack, then --verify (text and --json)
# agrees with the input and with hpfc-pack's build report.
verify_packed() {
    pfc=$1 what=$2
    shift 2
    run "$PACK" "$@" --json "$pfc" -o "$tmp/v.hpfc"
    expect_ok "pack $what"
    cp "$tmp/out" "$tmp/report.json"
    run "$INSPECT" --verify "$tmp/v.hpfc"
    expect_ok "verify $what"
    grep -q '^verdict *valid$' "$tmp/out" || fail "verify $what: no 'valid' verdict"
    grep -q '^Euler *V - E + F = 1 + C: ok$' "$tmp/out" || fail "verify $what: no Euler line"
    run "$INSPECT" --verify --json "$tmp/v.hpfc"
    expect_ok "verify --json $what"
    gcheck verified "$tmp/out" "$pfc" "$tmp/report.json" || fail "verify --json $what"
}

for pfc in "$TESTS"/data/valid/*.pfc; do
    name=$(basename "$pfc" .pfc)
    for sizes in "" "--root 3x2 --refine 3" "--root 1 --refine 2x4" "--flat"; do
        # shellcheck disable=SC2086 # $sizes holds several words
        verify_packed "$pfc" "$name ${sizes:-default}" $sizes
    done
done
for pfc in "$TESTS"/../data/*.pfc; do
    [ -e "$pfc" ] || continue
    name=$(basename "$pfc" .pfc)
    verify_packed "$pfc" "$name default"
    verify_packed "$pfc" "$name --root 1" --root 1
done

for f in "$TESTS"/data/valid/*.hpfc; do
    name=$(basename "$f")
    run "$INSPECT" --verify "$f"
    expect_ok "verify $name"
    run "$INSPECT" --verify --json "$f"
    expect_ok "verify --json $name"
    check json "$tmp/out" || fail "verify --json $name: bad JSON"
done

# expect_invalid FILE WHAT REASON: exit 1, one line naming FILE and holding
# REASON on stderr, a report saying INVALID on stdout, and the same as JSON
# (checked in full for the named reasons only: python3 is slow to start).
expect_invalid() {
    run "$INSPECT" --verify "$1"
    expect_one_line "verify $2" "hpfc-inspect: $1: "
    grep -qF -- "$3" "$tmp/err" || fail "verify $2: reason lacks '$3': $(cat "$tmp/err")"
    grep -q '^verdict *INVALID' "$tmp/out" || fail "verify $2: no INVALID verdict"
    run "$INSPECT" --verify --json "$1"
    expect_one_line "verify --json $2" "hpfc-inspect: $1: "
    grep -q '"valid":false' "$tmp/out" || fail "verify --json $2: not \"valid\":false"
    if [ -n "$3" ]; then
        gcheck invalid "$tmp/out" || fail "verify --json $2"
    fi
}

for f in "$TESTS"/data/invalid/*.hpfc; do
    name=$(basename "$f")
    case $name in
        bad_pool_checksum.hpfc) reason="checksum mismatch: section 0 (POOL) at offset" ;;
        corrupt_last_level_refined.hpfc) reason="corrupt pixel data" ;;
        *) reason="" ;;
    esac
    expect_invalid "$f" "$name" "$reason"
done
expect_invalid "$tmp/no-such-file" "a missing file" "No such file"

# One flipped pool bit: the section checksum catches it.
"$PACK" --quiet --root 1 "$TESTS/data/valid/two_components_hole.pfc" -o "$tmp/good.hpfc" ||
    fail "cannot pack the flip sample"
gcheck flip "$tmp/good.hpfc" "$tmp/flipped" 3 || fail "cannot flip bits"
for seed in 0 1 2; do
    expect_invalid "$tmp/flipped$seed.hpfc" "a flipped pool bit ($seed)" "checksum mismatch"
done

# Refined pixels that share one child image (checksums fixed up): every
# walk over the tree would revisit it once per parent, level by level.
# Addresses exist in the paper layout only (compact children are ranks).
"$PACK" --quiet --layout paper --root 1 "$TESTS/../data/delaunay-4000.pfc" -o "$tmp/deep.hpfc" ||
    fail "cannot pack the alias sample"
gcheck alias "$tmp/deep.hpfc" "$tmp/alias.hpfc" || fail "cannot alias images"
expect_invalid "$tmp/alias.hpfc" "aliased images" "starts at bit"

# Flipped bits with the checksums fixed up: the structural checks see them.
# Most flips are caught; some give another valid file (a word that still
# parses); none may crash, hang or print more than one line.
gcheck flip "$tmp/good.hpfc" "$tmp/fixed" 40 fix || fail "cannot flip bits"
caught=0
seed=0
while [ $seed -lt 40 ]; do
    f=$tmp/fixed$seed.hpfc
    run "$INSPECT" --verify "$f"
    case $rc in
        0) expect_ok "verify a re-checksummed flip ($seed)" ;;
        1)
            expect_one_line "verify a re-checksummed flip ($seed)" "hpfc-inspect: $f: "
            caught=$((caught + 1))
            ;;
        *) fail "verify a re-checksummed flip ($seed): exit status $rc (crash?)" ;;
    esac
    seed=$((seed + 1))
done
[ $caught -ge 30 ] || fail "re-checksummed flips: only $caught of 40 caught"

# Flipped bits in the LABL section (checksums fixed up): the stored labels
# are compared with the faces numbered again; a disagreement is one line
# naming the labels, never a crash.
gcheck flip "$tmp/good.hpfc" "$tmp/labl" 40 fix LABL || fail "cannot flip label bits"
caught=0
seed=0
while [ $seed -lt 40 ]; do
    f=$tmp/labl$seed.hpfc
    run "$INSPECT" --verify "$f"
    case $rc in
        0) expect_ok "verify a re-checksummed label flip ($seed)" ;;
        1)
            expect_one_line "verify a re-checksummed label flip ($seed)" "hpfc-inspect: $f: "
            caught=$((caught + 1))
            ;;
        *) fail "verify a re-checksummed label flip ($seed): exit status $rc (crash?)" ;;
    esac
    run "$INSPECT" --locate 0,0 "$f"
    [ "$rc" -le 1 ] || fail "locate on a label flip ($seed): exit status $rc (crash?)"
    seed=$((seed + 1))
done
[ $caught -ge 30 ] || fail "re-checksummed label flips: only $caught of 40 caught"

# The GEOM section: every packed file has it (hpfc-pack's default) and
# --verify checks it; --no-geometry leaves it out. Flipped bits in it
# (checksums fixed up) are one line naming the geometry, or another valid
# file (a coordinate moved within its leaf and its roads' order), never a
# crash; a query on the damaged file never crashes either.
run "$INSPECT" --verify "$tmp/good.hpfc"
grep -q '^geometry *GEOM section: ok$' "$tmp/out" || fail "verify: no geometry line"
"$PACK" --quiet --root 1 --no-geometry "$TESTS/data/valid/two_components_hole.pfc" \
    -o "$tmp/nogeom.hpfc" || fail "cannot pack without geometry"
run "$INSPECT" --verify "$tmp/nogeom.hpfc"
expect_ok "verify without GEOM"
grep -q '^geometry' "$tmp/out" && fail "verify: a geometry line without GEOM"
gcheck flip "$tmp/good.hpfc" "$tmp/geom" 40 fix GEOM || fail "cannot flip geometry bits"
caught=0
seed=0
while [ $seed -lt 40 ]; do
    f=$tmp/geom$seed.hpfc
    run "$INSPECT" --verify "$f"
    case $rc in
        0) expect_ok "verify a re-checksummed geometry flip ($seed)" ;;
        1)
            expect_one_line "verify a re-checksummed geometry flip ($seed)" "hpfc-inspect: $f: "
            caught=$((caught + 1))
            ;;
        *) fail "verify a re-checksummed geometry flip ($seed): exit status $rc (crash?)" ;;
    esac
    run "$INSPECT" --locate 0,0 "$f"
    [ "$rc" -le 1 ] || fail "locate on a geometry flip ($seed): exit status $rc (crash?)"
    seed=$((seed + 1))
done
[ $caught -ge 30 ] || fail "re-checksummed geometry flips: only $caught of 40 caught"

finish
