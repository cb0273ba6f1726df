#!/bin/sh
# Runs the libFuzzer harnesses (fuzz/README.md).
#
#   sh fuzz/run.sh [SECONDS] [HARNESS ...]   fuzz each harness for SECONDS
#                                            (default 60), one after another
#   sh fuzz/run.sh --merge [HARNESS ...]     minimise each harness's seeds
#                                            plus what the runs found back
#                                            into fuzz/corpus/HARNESS/, at
#                                            most 200 files and 2 MiB
#                                            (fuzz/cap_corpus.py)
#   sh fuzz/run.sh --check                   exit 0 iff clang can build
#                                            libFuzzer targets here
#
# Builds with clang, -fsanitize=fuzzer,address,undefined, in build-fuzz-clang
# (or $HPFC_FUZZ_BUILD), the library instrumented too. Each run reads the
# seed corpus fuzz/corpus/HARNESS/ and writes new inputs, the log and any
# crash / timeout / leak artifact under BUILD/fuzz-work/HARNESS/; the seed
# corpus is only changed by --merge. Exit status 1 if any run left an
# artifact (a finding) or failed to start, 2 on a usage error, 77 when clang
# or its libFuzzer runtime is missing.
set -eu
cd "$(dirname "$0")/.."
build=${HPFC_FUZZ_BUILD:-build-fuzz-clang}
all="open_buffer navigate_pixels traverse_darts read_labels read_geom parse_pfc roundtrip_graph decode_drc read_gis parse_points locate_batch read_shapes query_topology read_driver read_part read_pfc_chunks read_route read_range"

have_libfuzzer() {
    command -v clang >/dev/null 2>&1 && command -v clang++ >/dev/null 2>&1 || return 1
    tmp=$(mktemp -d)
    printf '%s\n' '#include <stddef.h>' '#include <stdint.h>' \
        'int LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { (void)d; (void)n; return 0; }' \
        >"$tmp/t.c"
    ok=0
    clang -fsanitize=fuzzer,address,undefined "$tmp/t.c" -o "$tmp/t" >/dev/null 2>&1 || ok=1
    rm -rf "$tmp"
    return $ok
}

mode=run
seconds=60
case "${1:-}" in
--check)
    have_libfuzzer
    exit $?
    ;;
--merge)
    mode=merge
    shift
    ;;
-*)
    echo "usage: sh fuzz/run.sh [SECONDS | --merge | --check] [HARNESS ...]" >&2
    exit 2
    ;;
[0-9]*)
    seconds=$1
    shift
    ;;
esac
harnesses=${*:-$all}
for h in $harnesses; do
    case " $all " in
    *" $h "*) ;;
    *)
        echo "fuzz/run.sh: unknown harness $h (one of: $all)" >&2
        exit 2
        ;;
    esac
done

if ! have_libfuzzer; then
    echo "fuzz/run.sh: clang with libFuzzer (libclang_rt.fuzzer) not found; skipped" >&2
    exit 77
fi

if [ ! -f "$build/build.ninja" ]; then
    # C++ too (hpfc-pack's Draco and projection sources), with the same flags
    # FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION (libFuzzer's convention)
    # lowers thresholds sized for real maps, so small inputs reach both sides
    flags="-fsanitize=fuzzer-no-link -fno-sanitize-recover=all -fsanitize-ignorelist=$PWD/fuzz/ubsan-ignorelist.txt -DFUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION"
    CC=clang CXX=clang++ meson setup "$build" -Dbuildtype=debugoptimized \
        -Db_sanitize=address,undefined -Db_lundef=false \
        "-Dc_args=$flags" "-Dcpp_args=$flags" >/dev/null
fi
# a build made before a harness was added lists it once meson has run again
ninja -C "$build" build.ninja >/dev/null
# read_gis exists only in builds with GIS input (GDAL, GEOS, GeographicLib)
built=$(ninja -C "$build" -t targets all | sed -n 's|^fuzz/fuzz_\([a-z_]*\): .*|\1|p' | tr '\n' ' ')
targets=""
kept=""
for h in $harnesses; do
    case " $built " in
    *" $h "*)
        targets="$targets fuzz/fuzz_$h"
        kept="$kept $h"
        ;;
    *) echo "$h: not in this build (no GIS input): skipped" >&2 ;;
    esac
done
harnesses=$kept
# shellcheck disable=SC2086
ninja -C "$build" $targets >/dev/null

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"
status=0
for h in $harnesses; do
    work="$build/fuzz-work/$h"
    mkdir -p "$work/corpus" "$work/artifacts"
    exe="$build/fuzz/fuzz_$h"
    if [ "$mode" = merge ]; then
        rm -rf "$work/merged" "$work/capped" "$work/merge.ctl"
        mkdir -p "$work/merged"
        if ! "$exe" -merge=1 -merge_control_file="$work/merge.ctl" -max_len=8192 -timeout=10 \
            "$work/merged" "fuzz/corpus/$h" "$work/corpus" >"$work/merge.log" 2>&1 ||
            ! python3 fuzz/cap_corpus.py "$work/merge.ctl" "$work/capped" 200 2097152 >"$work/cap.log"; then
            echo "$h: merge failed, see $work/merge.log" >&2
            status=1
            continue
        fi
        rm -f "fuzz/corpus/$h"/*
        cp "$work/capped"/* "fuzz/corpus/$h/"
        echo "$h: $(find "fuzz/corpus/$h" -type f | wc -l) files, $(cat "fuzz/corpus/$h"/* | wc -c) bytes ($(cat "$work/cap.log"))"
        continue
    fi
    before=$(find "$work/artifacts" -type f | wc -l)
    lsan=${LSAN_OPTIONS:-}
    if [ "$h" = read_gis ] || [ "$h" = read_driver ]; then # GDAL's own leaks: fuzz/lsan-gdal.supp
        lsan="suppressions=fuzz/lsan-gdal.supp:fast_unwind_on_malloc=0:print_suppressions=0"
    fi
    LSAN_OPTIONS=$lsan "$exe" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=8192 \
        -dict=fuzz/hpfc.dict -print_final_stats=1 -artifact_prefix="$work/artifacts/" \
        "$work/corpus" "fuzz/corpus/$h" >"$work/log" 2>&1 || true
    after=$(find "$work/artifacts" -type f | wc -l)
    last=$(grep -E '^#[0-9]+' "$work/log" | tail -n 1 || true)
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/log")
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$work/log")
    echo "$h: ${execs:-?} execs, ${rate:-?} exec/s; $last"
    if [ "$after" -gt "$before" ] || [ -z "$execs" ]; then
        echo "$h: FINDING (or failed to run): see $work/log and $work/artifacts/" >&2
        status=1
    fi
done
exit $status
