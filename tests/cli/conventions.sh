#!/bin/sh
# Command-line conventions of the tools, on the real
# hpfc-pack (PACK_BIN, not lib.sh's --force wrapper):
#  - -q is --quiet, -l is --layer;
#  - an existing OUTPUT is refused (exit 1, untouched) unless --force or
#    -overwrite (as ogr2ogr), and so is an existing OUT of hpfc-inspect's
#    --export-graph and --render;
#  - OUTPUT is checked before INPUT is read: an OUTPUT that cannot be made
#    is the one reason given even when INPUT is broken too;
#  - -o - writes the file to standard output (report on stderr), never a
#    file named '-';
#  - -o DIR/ and -o DIR say "is a directory";
#  - hpfc-inspect on a missing file says "No such file or directory", on a
#    directory "Is a directory".
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
# absolute paths: one check runs in $tmp
abs() { case $1 in /*) printf '%s' "$1" ;; *) printf '%s/%s' "$(pwd)" "$1" ;; esac; }
PACK_BIN=$(abs "$PACK_BIN") INSPECT=$(abs "$INSPECT") INSPECT_BIN=$(abs "$INSPECT_BIN") TESTS=$(abs "$TESTS")
PFC=$TESTS/data/valid/square_diagonal.pfc

# -q, --quiet
run "$PACK_BIN" -q "$PFC" -o "$tmp/q.hpfc"
expect_ok "-q"
[ -s "$tmp/out" ] && fail "-q printed a report"
[ -s "$tmp/q.hpfc" ] || fail "-q wrote no file"

# an existing OUTPUT: refused, untouched; --force and -overwrite replace it
printf 'precious\n' >"$tmp/existing.hpfc"
run "$PACK_BIN" "$PFC" -o "$tmp/existing.hpfc"
expect_error "existing OUTPUT" "hpfc-pack: " 1
grep -q "exists; --force (or -overwrite) replaces it" "$tmp/err" || fail "reason: $(cat "$tmp/err")"
check unchanged "$tmp/existing.hpfc" "precious
" || fail "the existing OUTPUT was changed"
[ -s "$tmp/out" ] && fail "a refused run printed a report"
for flag in --force -overwrite; do
    printf 'precious\n' >"$tmp/existing.hpfc"
    run "$PACK_BIN" -q $flag "$PFC" -o "$tmp/existing.hpfc"
    expect_ok "$flag"
    cmp -s "$tmp/existing.hpfc" "$tmp/q.hpfc" || fail "$flag did not replace OUTPUT with the map"
done

# OUTPUT checked before INPUT is read
run "$PACK_BIN" "$tmp/no-such-input.pfc" -o "$tmp/no-such-dir/out.hpfc"
expect_error "bad OUTPUT and missing INPUT" "hpfc-pack: " 1
grep -q "no-such-dir/out.hpfc: cannot create: No such file or directory" "$tmp/err" ||
    fail "OUTPUT not checked first: $(cat "$tmp/err")"
run "$PACK_BIN" "$tmp/no-such-input.pfc" -o "$tmp/q.hpfc"
expect_error "existing OUTPUT and missing INPUT" "hpfc-pack: " 1
grep -q "exists" "$tmp/err" || fail "existing OUTPUT not checked first: $(cat "$tmp/err")"
if [ "$(id -u)" -ne 0 ]; then # root writes anywhere
    mkdir "$tmp/ro" && chmod 555 "$tmp/ro"
    run "$PACK_BIN" "$PFC" -o "$tmp/ro/out.hpfc"
    expect_error "read-only directory" "hpfc-pack: " 1
    grep -q "cannot create: Permission denied" "$tmp/err" || fail "read-only: $(cat "$tmp/err")"
fi

# -o DIR/, -o DIR
mkdir "$tmp/outdir"
for out in "$tmp/outdir/" "$tmp/outdir" "$tmp/not-yet/"; do
    run "$PACK_BIN" "$PFC" -o "$out"
    expect_error "-o $out" "hpfc-pack: " 2
    grep -q "is a directory" "$tmp/err" || fail "-o $out: $(cat "$tmp/err")"
done
[ -n "$(ls -A "$tmp/outdir")" ] && fail "-o DIR left $(ls -A "$tmp/outdir") behind"

# -o -: the file on stdout, the report on stderr, no file named '-'
(cd "$tmp" && "$PACK_BIN" --json "$PFC" -o - >"$tmp/stdout.hpfc" 2>"$tmp/err") ||
    fail "-o -: exit status $?: $(cat "$tmp/err")"
[ -e "$tmp/-" ] && fail "-o - wrote a file named '-'"
cmp -s "$tmp/stdout.hpfc" "$tmp/q.hpfc" || fail "-o -: standard output is not the packed file"
check json "$tmp/err" || fail "-o - --json: the report on stderr is not JSON"
run "$INSPECT" --verify "$tmp/stdout.hpfc"
expect_ok "--verify of the file from standard output"

# hpfc-inspect: the system's reason for a file it cannot open
run "$INSPECT" "$tmp/no-such-file.hpfc"
expect_error "inspect a missing file" "hpfc-inspect: " 1
grep -qx "hpfc-inspect: $tmp/no-such-file.hpfc: No such file or directory" "$tmp/err" ||
    fail "missing file: $(cat "$tmp/err")"
run "$INSPECT" --locate 1,1 "$tmp/outdir"
expect_error "inspect a directory" "hpfc-inspect: " 1
grep -q "Is a directory" "$tmp/err" || fail "directory: $(cat "$tmp/err")"

# -l is --layer (GIS input only)
run "$PACK_BIN" -q -l nosuch "$TESTS/data/gis/ok/duplicate_borders.geojson" -o "$tmp/l.hpfc"
if ! grep -q "not built in" "$tmp/err"; then
    expect_error "-l nosuch" "hpfc-pack: " 1
    grep -q "no layer 'nosuch'" "$tmp/err" || fail "-l: $(cat "$tmp/err")"
fi

# hpfc-inspect's outputs (--export-graph, --render): an existing OUT is
# refused, untouched, before any work; --force and -overwrite replace it
for out in graph.json map.svg; do
    case $out in *.json) mode=--export-graph ;; *) mode=--render ;; esac
    printf 'precious\n' >"$tmp/$out"
    run "$INSPECT_BIN" $mode "$tmp/$out" "$tmp/q.hpfc"
    expect_error "$mode over an existing OUT" "hpfc-inspect: " 1
    grep -q "exists; --force (or -overwrite) replaces it" "$tmp/err" || fail "reason: $(cat "$tmp/err")"
    check unchanged "$tmp/$out" "precious
" || fail "$mode changed the existing OUT"
    for flag in --force -overwrite; do
        printf 'precious\n' >"$tmp/$out"
        run "$INSPECT_BIN" $mode "$tmp/$out" $flag "$tmp/q.hpfc"
        expect_ok "$mode $flag"
        grep -q precious "$tmp/$out" && fail "$mode $flag did not replace OUT"
    done
done

# both tools' --help list the options of the conventions
run "$PACK_BIN" --help
for opt in "-q, --quiet" "-l, --layer" "--force, -overwrite" "-a_srs" "-s_srs" "--invalid node|reject"; do
    grep -q -- "$opt" "$tmp/out" || fail "hpfc-pack --help lacks $opt"
done
run "$INSPECT" --help
for opt in --window-lonlat --size --lon-col --lat-col --id-col --format --locate-batch "--force, -overwrite"; do
    grep -q -- "$opt" "$tmp/out" || fail "hpfc-inspect --help lacks $opt"
done

finish
