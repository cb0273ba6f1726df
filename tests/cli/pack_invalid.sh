#!/bin/sh
# Every tests/data/invalid/*.pfc is refused: exit 1, exactly one stderr line
# "hpfc-pack: ...", nothing on stdout, no file left in the output directory
# (not even a temporary one), and an existing output untouched.
# pack_invalid.expect gives, for some fixtures, words the reason must contain.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

dir=$tmp/outdir
mkdir "$dir"

# the names in DIR other than those given
others() {
    d=$1
    shift
    for f in "$d"/* "$d"/.[!.]*; do
        [ -e "$f" ] || continue
        keep=0
        for k in "$@"; do [ "$(basename "$f")" = "$k" ] && keep=1; done
        [ $keep -eq 0 ] && printf '%s ' "$(basename "$f")"
    done
}

for pfc in "$TESTS"/data/invalid/*.pfc; do
    name=$(basename "$pfc")
    run "$PACK" --json "$pfc" -o "$dir/fresh.hpfc"
    expect_error "$name" "hpfc-pack: " 1
    [ -s "$tmp/out" ] && fail "$name: printed a report"
    left=$(others "$dir")
    [ -n "$left" ] && fail "$name: left $left behind"
    want=$(awk -v n="$name" '$1 == n { sub(/^[^ ]+ +/, ""); print }' "$HERE/pack_invalid.expect")
    if [ -n "$want" ] && ! grep -qF -- "$want" "$tmp/err"; then
        fail "$name: reason lacks '$want': $(cat "$tmp/err")"
    fi

    printf 'precious' >"$dir/existing.hpfc"
    run "$PACK" "$pfc" -o "$dir/existing.hpfc"
    expect_error "$name over an existing file" "hpfc-pack: " 1
    check unchanged "$dir/existing.hpfc" precious || fail "$name: existing output modified"
    left=$(others "$dir" existing.hpfc)
    [ -n "$left" ] && fail "$name: left $left behind"
    rm -f "$dir/existing.hpfc"
done

finish
