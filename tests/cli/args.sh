#!/bin/sh
# Command lines and their verdicts, from args.expect: exit status, tool and
# arguments. A failure must print exactly one line "TOOL: ..." on stderr and,
# for hpfc-pack, leave no OUT behind; a success must print nothing on stderr.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

# FILE: a valid packed file; GARBAGE, EMPTY, TRUNCATED: files that are not.
"$PACK" --quiet "$TESTS/data/valid/square_diagonal.pfc" -o "$tmp/packed.hpfc" ||
    fail "cannot pack the sample"
printf 'this is not an hpfc file, just some text\n' >"$tmp/garbage"
: >"$tmp/empty"
head -c 100 "$tmp/packed.hpfc" >"$tmp/truncated"
printf 'a,b\n1,2\n' >"$tmp/table.csv"

while read -r status tool args; do
    case $status in '#'* | '') continue ;; esac
    set --
    for word in $args; do
        case $word in
            GARBAGE | EMPTY | TRUNCATED) word=$tmp/$(echo "$word" | tr '[:upper:]' '[:lower:]') ;;
            CSV) word=$tmp/table.csv ;;
            MISSING) word=$tmp/no-such-file ;;
            --*=OUT) word=${word%OUT}$tmp/out.hpfc ;; # not the working directory's OUT
            *) word=$(substitute "$word") ;;
        esac
        set -- "$@" "$word"
    done
    case $tool in
        pack) prog=$PACK prefix="hpfc-pack: " ;;
        inspect) prog=$INSPECT prefix="hpfc-inspect: " ;;
        *) fail "args.expect: unknown tool $tool"; continue ;;
    esac
    rm -f "$tmp/out.hpfc"
    run "$prog" "$@"
    if [ "$status" -eq 0 ]; then
        expect_ok "$tool $args"
    else
        expect_error "$tool $args" "$prefix" "$status"
        [ -e "$tmp/out.hpfc" ] && fail "$tool $args: left OUT behind"
    fi
    case " $args " in
        *" --json "*) [ "$status" -eq 0 ] && { check json "$tmp/out" || fail "$tool $args: bad JSON"; } ;;
    esac
done <"$HERE/args.expect"

finish
