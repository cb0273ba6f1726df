# lib.sh: sourced by the CLI contract tests. POSIX sh.
#
# Every test script is called as: sh SCRIPT.sh HPFC_PACK HPFC_INSPECT TESTS_DIR
# (meson passes the built tools and tests/). It runs its checks, prints one
# line per failure and exits 1 if any check failed.

# shellcheck disable=SC2034 # used by the scripts that source this file
PACK=$1
# shellcheck disable=SC2034
INSPECT=$2
TESTS=$3
HERE=$TESTS/cli
# check CMD ARGS...: one of the checks of check.py
check() {
    python3 "$HERE/check.py" "$@"
}
failures=0

tmp=$(mktemp -d "${TMPDIR:-/tmp}/hpfc-cli.XXXXXX") || exit 1
trap 'rm -rf "$tmp"' EXIT INT TERM

# Both tools refuse an existing output without --force. The
# scripts write to the same paths again and again, so $PACK and $INSPECT
# are the tools with --force; PACK_BIN and INSPECT_BIN are the tools
# themselves, for the checks of the refusal (cli_conventions).
PACK_BIN=$PACK
printf '#!/bin/sh\nexec "%s" --force "$@"\n' "$PACK_BIN" >"$tmp/hpfc-pack-force"
chmod +x "$tmp/hpfc-pack-force"
PACK=$tmp/hpfc-pack-force
INSPECT_BIN=$INSPECT
printf '#!/bin/sh\nexec "%s" --force "$@"\n' "$INSPECT_BIN" >"$tmp/hpfc-inspect-force"
chmod +x "$tmp/hpfc-inspect-force"
INSPECT=$tmp/hpfc-inspect-force

fail() {
    echo "FAIL: $*"
    failures=$((failures + 1))
}

# run CMD ARGS...: stdout to $tmp/out, stderr to $tmp/err, exit status in $rc.
run() {
    rc=0
    "$@" </dev/null >"$tmp/out" 2>"$tmp/err" || rc=$?
}

# expect_error WHAT PREFIX RC: the last run failed with status RC and printed
# exactly one line starting with PREFIX on stderr.
expect_error() {
    if [ "$rc" -ne "$3" ]; then
        fail "$1: exit status $rc, expected $3 (stderr: $(head -c 300 "$tmp/err"))"
    elif ! check oneline "$tmp/err" "$2" >/dev/null 2>"$tmp/why"; then
        fail "$1: $(cat "$tmp/why")"
    fi
}

# expect_ok WHAT: the last run exited 0 with nothing on stderr.
expect_ok() {
    if [ "$rc" -ne 0 ] || [ -s "$tmp/err" ]; then
        fail "$1: exit status $rc, stderr: $(head -c 300 "$tmp/err")"
    fi
}

# substitute WORD: the placeholders of the expectation files.
substitute() {
    case $1 in
        INPUT) printf '%s' "$TESTS/data/valid/square_diagonal.pfc" ;;
        OUT) printf '%s' "$tmp/out.hpfc" ;;
        FILE) printf '%s' "$tmp/packed.hpfc" ;;
        *) printf '%s' "$1" ;;
    esac
}

finish() {
    if [ "$failures" -ne 0 ]; then
        echo "$failures check(s) failed"
        exit 1
    fi
    echo "all checks passed"
    exit 0
}
