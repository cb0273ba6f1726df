#!/bin/sh
# hpfc-pack on Draco meshes (interfaces §2). The fixtures of
# tests/data/mesh/ pack to the verdicts of draco.expect: those of ok/ to
# counts, the same topology as the mesh's .pfc twin (the very same exported
# map when the positions are lossless) and files hpfc-inspect --verify
# accepts; those of bad/ to clear refusals. Every file of ok/ and bad/ must
# have its line there, so none sits untested under the wrong verdict. Then: Draco found by content, from standard input, and corrupt
# input: every 7th prefix of a fixture, a suffix without the magic and
# bit flips in the header fail with exit 1, one stderr line and no output;
# single-bit flips anywhere either fail the same way or decode to a mesh
# whose file verifies. A build without Draco must refuse .drc with exit 2
# and say that Draco is not built in.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
MESH=$TESTS/data/mesh
OK=$MESH/ok
BAD=$MESH/bad

# The directory is the verdict: each file of ok/ is a `pack` fixture or its
# twin, each file of bad/ a `fail` fixture. Checked first, as it needs no
# Draco: a file dropped in either without its line would otherwise never run.
awk '$1 == "pack" { print $2; if ($3 != "-") print $3 }' "$HERE/draco.expect" |
    LC_ALL=C sort -u >"$tmp/want-ok"
awk '$1 == "fail" { print $2 }' "$HERE/draco.expect" | LC_ALL=C sort -u >"$tmp/want-bad"
for d in ok bad; do
    (cd "$MESH/$d" && LC_ALL=C ls) >"$tmp/have-$d"
    for f in $(LC_ALL=C comm -23 "$tmp/want-$d" "$tmp/have-$d"); do
        fail "draco.expect names $f, which is not in mesh/$d/"
    done
    for f in $(LC_ALL=C comm -13 "$tmp/want-$d" "$tmp/have-$d"); do
        fail "mesh/$d/$f has no line of its verdict in draco.expect"
    done
done

run "$PACK" --quiet "$OK/cluster_lossless.drc" -o "$tmp/probe.hpfc"
if [ "$rc" -eq 2 ]; then
    expect_error "pack .drc without Draco" "hpfc-pack: " 2
    grep -q "needs Draco, not built in" "$tmp/err" ||
        fail "pack .drc without Draco: unclear reason: $(cat "$tmp/err")"
    [ -e "$tmp/probe.hpfc" ] && fail "pack .drc without Draco: left OUT behind"
    echo "Draco is not built in: only its refusal was checked"
    finish
fi
expect_ok "pack cluster_lossless.drc"

# numbers FILE KEY...: the values of the JSON object's keys, space separated
numbers() {
    python3 -c 'import json, sys
r = json.load(open(sys.argv[1]))
print(" ".join(str(r.get(k)) for k in sys.argv[2:]))' "$@"
}

# fails WHAT: the last run exited 1 with one line "hpfc-pack: ..." on stderr,
# nothing on stdout and no $tmp/out.hpfc (no python: it runs a thousand times)
fails() {
    if [ "$rc" -ne 1 ]; then
        fail "$1: exit status $rc, expected 1 ($(head -c 200 "$tmp/err"))"
    elif [ "$(wc -l <"$tmp/err")" -ne 1 ] || [ "$(head -c 11 "$tmp/err")" != "hpfc-pack: " ]; then
        fail "$1: stderr is not one 'hpfc-pack: ' line: $(head -c 300 "$tmp/err")"
    fi
    [ -s "$tmp/out" ] && fail "$1: printed a report"
    [ -e "$tmp/out.hpfc" ] && fail "$1: left OUT behind"
    rm -f "$tmp/out.hpfc"
}

# ---- the fixtures ---------------------------------------------------------------
while read -r verb fixture rest; do
    case $verb in '#'* | '') continue ;; esac
    rm -f "$tmp/out.hpfc"
    case $verb in
    pack)
        # shellcheck disable=SC2086 # rest holds several words
        set -- $rest
        twin=$1 match=$2 want="$3 $4 $5 $6"
        run "$PACK" --json "$OK/$fixture" -o "$tmp/out.hpfc"
        expect_ok "$fixture"
        [ -f "$tmp/out.hpfc" ] || { fail "$fixture: no output file"; continue; }
        cp "$tmp/out" "$tmp/report.json"
        got=$(numbers "$tmp/report.json" vertices edges faces components)
        [ "$got" = "$want" ] || fail "$fixture: V E F C = $got, expected $want"
        [ "$(numbers "$tmp/report.json" input_format)" = draco ] ||
            fail "$fixture: input_format is not draco"
        run "$INSPECT" --json "$tmp/out.hpfc"
        expect_ok "$fixture: inspect"
        check agree "$tmp/report.json" "$tmp/out" || fail "$fixture: inspect disagrees"
        run "$INSPECT" --verify "$tmp/out.hpfc"
        expect_ok "$fixture: verify"
        [ "$twin" = - ] && continue
        check report "$tmp/report.json" "$OK/$twin" || fail "$fixture: counts differ from $twin"
        run "$PACK" --json "$OK/$twin" -o "$tmp/twin.hpfc"
        expect_ok "$twin"
        got=$(numbers "$tmp/out" vertices edges faces components)
        [ "$got" = "$want" ] || fail "$twin: V E F C = $got, expected $want"
        if [ "$match" = exact ]; then
            run "$INSPECT" --export-graph "$tmp/drc.json" "$tmp/out.hpfc"
            expect_ok "$fixture: export"
            run "$INSPECT" --export-graph "$tmp/pfc.json" "$tmp/twin.hpfc"
            expect_ok "$twin: export"
            cmp -s "$tmp/drc.json" "$tmp/pfc.json" ||
                fail "$fixture: the exported map differs from $twin's"
        fi
        ;;
    fail)
        run "$PACK" --json "$BAD/$fixture" -o "$tmp/out.hpfc"
        fails "$fixture"
        grep -qF -- "$rest" "$tmp/err" || fail "$fixture: reason lacks '$rest': $(cat "$tmp/err")"
        ;;
    *) fail "draco.expect: unknown verb $verb" ;;
    esac
done <"$HERE/draco.expect"

# ---- found by content, read from standard input -----------------------------------
cp "$OK/cluster_q11.drc" "$tmp/mesh.bin"
run "$PACK" --json "$tmp/mesh.bin" -o "$tmp/out.hpfc"
expect_ok "a .drc named .bin"
[ "$(numbers "$tmp/out" input_format vertices)" = "draco 5" ] || fail "a .drc named .bin: report"
rc=0
"$PACK" --json - -o "$tmp/stdin.hpfc" <"$OK/cluster_q11.drc" >"$tmp/out" 2>"$tmp/err" || rc=$?
expect_ok "a .drc on standard input"
[ "$(numbers "$tmp/out" input_format vertices)" = "draco 5" ] || fail "standard input: report"

# a failure leaves an existing OUTPUT alone
printf 'precious' >"$tmp/existing.hpfc"
run "$PACK" "$BAD/fold.drc" -o "$tmp/existing.hpfc"
expect_error "fold.drc over an existing file" "hpfc-pack: " 1
check unchanged "$tmp/existing.hpfc" precious || fail "fold.drc: existing output modified"

# ---- corrupt input --------------------------------------------------------------------
# (Every hpfc-pack run costs tens of milliseconds of loading GDAL: the sweeps
# below are sized to stay within a few hundred runs.)
rm -f "$tmp/out.hpfc"
printf 'this is no mesh\n' >"$tmp/fake.drc"
: >"$tmp/empty.drc"
for f in fake.drc empty.drc; do
    run "$PACK" "$tmp/$f" -o "$tmp/out.hpfc"
    fails "$f"
    grep -q 'not a Draco file' "$tmp/err" || fail "$f: reason: $(cat "$tmp/err")"
done

size=$(wc -c <"$OK/delaunay_q11.drc")
n=0
while [ "$n" -lt "$size" ]; do
    head -c "$n" "$OK/delaunay_q11.drc" >"$tmp/cut.drc"
    run "$PACK" --json "$tmp/cut.drc" -o "$tmp/out.hpfc"
    fails "delaunay_q11.drc cut to $n bytes"
    n=$((n + 7))
done

# Single-bit flips. In the magic and the major version they must fail; in the
# rest of the file a flip may still decode (a moved point, another quantized
# value), and then the file written must verify.
mkdir "$tmp/flip"
python3 - "$tmp/flip" "$OK/cluster_q11.drc" 2 "$OK/delaunay_q11.drc" 37 <<'PY'
import os, sys
out = sys.argv[1]
for path, step in zip(sys.argv[2::2], sys.argv[3::2]):
    data = open(path, "rb").read()
    name = os.path.basename(path)[:-4]
    for i in list(range(6)) + list(range(6, len(data), int(step))):
        for bit in [i % 8, 7 - i % 8] if i < 6 else [i % 8]:
            d = bytearray(data)
            d[i] ^= 1 << bit
            kind = "header" if i < 6 else "body"
            with open(f"{out}/{kind}-{name}-{i}-{bit}.drc", "wb") as f:
                f.write(d)
PY
decoded=0
for f in "$tmp"/flip/*.drc; do
    what="bit flip $(basename "$f" .drc)"
    run "$PACK" --quiet "$f" -o "$tmp/out.hpfc"
    case $(basename "$f") in
    header-*) fails "$what" ;;
    *)
        if [ "$rc" -eq 0 ]; then
            decoded=$((decoded + 1))
            run "$INSPECT" --verify "$tmp/out.hpfc"
            expect_ok "$what: verify"
            rm -f "$tmp/out.hpfc"
        else
            fails "$what"
        fi
        ;;
    esac
done
echo "bit flips: $decoded of the body flips still decoded to a valid mesh"

finish
