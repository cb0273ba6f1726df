#!/bin/sh
# hpfc-inspect reads FILE from standard input ('-') and from pipes in every
# mode (interfaces §3): each mode run on `cat FILE |` ... `-` and on a FIFO
# fed by cat must print what the same command prints on the path, and write
# the same OUT byte for byte (the oracle: the path, which is mapped, against
# the bytes read into memory). Among them the modes that read FILE twice
# before (--export-graph verified it first; --dissolve --export exported
# the open file again) and --render, whose OUT is named after OUT alone.
# Refusals: POINTS and FILE both standard input; OUT that is the file
# standard input is redirected from. The GIS modes (--export, --neighbours,
# --dissolve*, --mesh --export) run only when GDAL is built in.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

# normalize OUTPUT NAME OUT: the outputs name FILE (and OUT); FILE is
# written as '-' (the pipe's name) and OUT as OUT, and the timings dropped,
# so that the runs compare.
normalize() {
    sed -e "s|$2|-|g" -e "s|$3|OUT|g" -e '/^time /d' -e 's/"seconds":[0-9.e+-]*//' "$1"
}

# same MODE FILE OUTEXT OPTIONS...: OPTIONS [OUT] FILE on the path, on a pipe
# and on a FIFO; OUTEXT non-empty: the mode writes OUT ($tmp/o-VARIANT.EXT,
# given after OPTIONS' last word, which must be the option taking it).
same() {
    mode=$1 file=$2 ext=$3
    shift 3
    for variant in path pipe fifo; do
        out=
        [ -n "$ext" ] && out=$tmp/o-$variant.$ext && rm -rf "$out"
        rc=0
        case $variant in
            path)
                "$INSPECT" "$@" ${out:+"$out"} "$file" >"$tmp/out" 2>"$tmp/err" </dev/null || rc=$?
                name=$file ;;
            pipe)
                # shellcheck disable=SC2002 # a pipe, not a redirected file, on purpose
                cat "$file" | "$INSPECT" "$@" ${out:+"$out"} - >"$tmp/out" 2>"$tmp/err" || rc=$?
                name=/nonexistent ;;
            fifo)
                rm -f "$tmp/fifo"
                mkfifo "$tmp/fifo"
                cat "$file" >"$tmp/fifo" &
                writer=$!
                "$INSPECT" "$@" ${out:+"$out"} "$tmp/fifo" >"$tmp/out" 2>"$tmp/err" </dev/null || rc=$?
                # a tool that never opened the FIFO leaves cat blocked in open()
                kill "$writer" 2>/dev/null
                wait "$writer" 2>/dev/null
                name=$tmp/fifo ;;
        esac
        expect_ok "$mode: $variant"
        normalize "$tmp/out" "$name" "${out:-/nonexistent}" >"$tmp/$variant.txt"
        [ -s "$tmp/$variant.txt" ] || fail "$mode: $variant: nothing printed"
        if [ "$variant" != path ]; then
            cmp -s "$tmp/path.txt" "$tmp/$variant.txt" ||
                fail "$mode: $variant prints otherwise than the path: $(diff "$tmp/path.txt" "$tmp/$variant.txt" | head -5)"
            [ -z "$ext" ] || cmp -s "$tmp/o-path.$ext" "$out" ||
                fail "$mode: $variant writes another OUT than the path"
        fi
    done
}

run "$PACK" -q "$TESTS/data/valid/polyline_decimals.pfc" -o "$tmp/p.hpfc"
expect_ok "pack polyline_decimals"
p=$tmp/p.hpfc
same "summary" "$p" ""
same "summary --json" "$p" "" --json
same "--verify" "$p" "" --verify
same "--verify --json" "$p" "" --verify --json
same "--sections" "$p" "" --sections
same "--stats" "$p" "" --stats
same "--window" "$p" "" --window 0,0,1,1 --json
same "--nearest" "$p" "" --nearest 0.5,0.25
same "--locate" "$p" "" --locate 0.5,0.25
same "--export-graph" "$p" json --export-graph
same "--render" "$p" svg --json --render

# The check is able to fail: a pipe that carries half the file is refused.
head -c 4000 "$p" | "$INSPECT" --verify - >"$tmp/out" 2>"$tmp/err" && fail "--verify of half a file passed"

# POINTS and FILE cannot both come from standard input.
echo "0.5,0.25" | "$INSPECT" --locate-batch - - >"$tmp/out" 2>"$tmp/err"
rc=$?
expect_error "--locate-batch - -" "hpfc-inspect: --locate-batch: POINTS and FILE cannot both be standard input" 2

# OUT that is the file behind standard input is FILE: refused even with --force.
cp "$p" "$tmp/in.hpfc"
rc=0
# shellcheck disable=SC2094 # reading OUT is the point: it must not be written
"$INSPECT" --export-graph "$tmp/in.hpfc" - <"$tmp/in.hpfc" >"$tmp/out" 2>"$tmp/err" || rc=$?
expect_error "--export-graph OUT - <OUT" "hpfc-inspect: $tmp/in.hpfc: OUT is FILE" 2
cmp -s "$p" "$tmp/in.hpfc" || fail "--export-graph OUT - <OUT: the input was overwritten"

run "$PACK" -q --key i "$TESTS/data/gis/ok/duplicate_borders.geojson" -o "$tmp/g.hpfc"
if grep -q "not built in" "$tmp/err"; then
    echo "GIS input not built in: --export, --neighbours and --dissolve skipped"
    finish
fi
expect_ok "pack duplicate_borders"
g=$tmp/g.hpfc
same "--export" "$g" geojson --export
same "--export --json" "$g" geojson --json --export
same "--export-faces" "$g" geojson --export-faces
same "--neighbours" "$g" "" --neighbours 0
same "--neighbours --json" "$g" "" --json --neighbours 0
same "--dissolve --export" "$g" geojson --dissolve source_fid --export
same "--dissolve-features" "$g" "" --dissolve-features 0,1
same "--dissolve-features --export" "$g" geojson --dissolve-features 0,1 --export
same "--mesh --export" "$g" geojson --mesh --export
finish
