#!/bin/sh
# hpfc-inspect's queries against inspect_views.expect (exit status, one-line
# stderr on failure, JSON equal to a golden output), then pictures: a PNG of
# the requested size that is not blank, and an SVG that parses as XML.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

DATA=$TESTS/data
views() {
    python3 "$HERE/views_check.py" "$@"
}
printf 'this is not an hpfc file, just some text\n' >"$tmp/garbage"
mkdir "$tmp/outdir"

while read -r status golden args; do
    case $status in '#'* | '') continue ;; esac
    set --
    for word in $args; do
        case $word in
            HOLE) word=$DATA/valid/two_components_hole_crs.hpfc ;;
            SQUARE) word=$DATA/valid/square_diagonal.hpfc ;;
            LOOP) word=$DATA/valid/loop_quadtree.hpfc ;;
            BORDERS) word=$DATA/valid/borders_1_2.hpfc ;;
            BADPOOL) word=$DATA/invalid/bad_pool_checksum.hpfc ;;
            GARBAGE) word=$tmp/garbage ;;
            OUTDIR/*) word=$tmp/outdir/${word#OUTDIR/} ;;
        esac
        set -- "$@" "$word"
    done
    run "$INSPECT" "$@"
    if [ "$status" -eq 0 ]; then
        expect_ok "$args"
    else
        expect_error "$args" "hpfc-inspect: " "$status"
    fi
    [ -s "$tmp/out" ] || [ "$status" -ne 0 ] || fail "$args: printed nothing"
    if [ "$golden" != - ]; then
        views same "$tmp/out" "$HERE/views/$golden" || fail "$args: output differs from $golden"
    else
        case " $args " in
            *" --json "*) [ "$status" -eq 0 ] && { check json "$tmp/out" || fail "$args: bad JSON"; } ;;
        esac
    fi
done <"$HERE/inspect_views.expect"

hole=$DATA/valid/two_components_hole_crs.hpfc
# a PNG of the requested size, not blank (when this build has cairo)
run "$INSPECT" --render "$tmp/outdir/hole.png" --size 320x240 "$hole"
if [ "$rc" -eq 0 ]; then
    views png "$tmp/outdir/hole.png" 320 240 || fail "--render PNG: bad picture"
elif grep -q 'no PNG output' "$tmp/err"; then
    echo "note: this build has no cairo; PNG not checked"
else
    fail "--render PNG: exit status $rc: $(cat "$tmp/err")"
fi
# an SVG with the window's aspect and the edges drawn
run "$INSPECT" --render "$tmp/outdir/hole.svg" --size 400 --window=-20,0,40,30 "$hole"
expect_ok "--render SVG"
views svg "$tmp/outdir/hole.svg" 400 200 || fail "--render SVG: bad picture"
# --render never writes over its input
cp "$hole" "$tmp/copy.hpfc"
cp "$hole" "$tmp/copy.svg"
run "$INSPECT" --render "$tmp/copy.svg" "$tmp/copy.svg"
[ "$rc" -ne 0 ] && cmp -s "$hole" "$tmp/copy.svg" || fail "--render overwrote its input"

# every valid fixture: --stats and --sections succeed
for f in "$DATA"/valid/*.hpfc; do
    run "$INSPECT" --stats --json "$f"
    expect_ok "--stats $(basename "$f")"
    run "$INSPECT" --sections "$f"
    expect_ok "--sections $(basename "$f")"
done

finish
