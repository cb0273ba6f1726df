#!/bin/sh
# Builds hpfc from scratch with AddressSanitizer and UndefinedBehaviorSanitizer
# and runs the whole test suite; ends with one "N passed, N failed" line.
set -eu
cd "$(dirname "$0")/.."
sh tools/install-deps.sh
rm -rf build-test
meson setup build-test -Db_sanitize=address,undefined -Db_lundef=false -Dwerror=true >/dev/null
ninja -C build-test
status=0
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    meson test -C build-test --print-errorlogs --num-processes 2 || status=$?
# A bounded libFuzzer run of every harness (fuzz/README.md), only where clang
# and its libFuzzer runtime exist: a missing clang skips it, a finding fails.
# HPFC_FUZZ_SECONDS (default 30 per harness; 0 skips) sets its length.
fuzz_seconds=${HPFC_FUZZ_SECONDS:-30}
if [ "$fuzz_seconds" -gt 0 ] && sh fuzz/run.sh --check; then
    rm -rf build-fuzz-ci
    HPFC_FUZZ_BUILD=build-fuzz-ci sh fuzz/run.sh "$fuzz_seconds" || { echo "fuzz: FAILED"; status=1; }
else
    echo "fuzz: skipped (no clang with libFuzzer, or HPFC_FUZZ_SECONDS=0)"
fi
# Many readers at once under ThreadSanitizer: tests/lib/test_threads.c (8
# threads on one file, each query against one thread's answer) built with
# clang -fsanitize=thread, that program alone (what it links: the library
# and the test generator), so the step costs about a minute; then
# tests/lib/test_faces_threads.c (faces numbered on up to 8 threads, a
# smaller sweep than the ASan run's: about 30 s) and
# tests/lib/test_build_threads.c (validation and the build's levels on up
# to 8 threads, a smaller sweep too), tests/tools/test_sort.c (hpfc-pack's
# sort on up to 4 threads), tests/tools/test_segnode.c (the noding's
# search for crossing segments on up to 3 threads) and
# tests/tools/test_segment_graph.c (the graph's segment ends numbered on up
# to 3 threads). Then
# hpfc-pack's parts built on 4 threads (--jobs): the shipped sample, whose
# bytes must be the whole build's, and a graph whose edges cross, refused
# in the whole build's words; then two GIS layers with polygons, whose
# linking finds the faces' witnesses on a second thread (their bytes must
# be the ASan build's; GDAL's own lock order, taken on one thread, is not
# what this checks: detect_deadlocks=0 there). Any report fails it.
# Skipped without clang.
tsan_gis() {
    for layer in counties_ne countries_world; do
        TSAN_OPTIONS=halt_on_error=1:exitcode=66:detect_deadlocks=0 build-tsan/hpfc-pack/hpfc-pack -q --threads 2 \
            "tests/data/gis/$layer.geojson" -o "$1/$layer.hpfc" &&
            build-test/hpfc-pack/hpfc-pack -q "tests/data/gis/$layer.geojson" -o "$1/$layer.ref.hpfc" &&
            cmp "$1/$layer.hpfc" "$1/$layer.ref.hpfc" || return 1
    done
}
tsan_pack() {
    pack=build-tsan/hpfc-pack/hpfc-pack
    t=$(mktemp -d)
    TSAN_OPTIONS=halt_on_error=1:exitcode=66 $pack -q data/delaunay-4000.pfc -o "$t/whole.hpfc" &&
        TSAN_OPTIONS=halt_on_error=1:exitcode=66 $pack -q --partitions 16 --jobs 4 \
            data/delaunay-4000.pfc -o "$t/jobs.hpfc" &&
        cmp "$t/whole.hpfc" "$t/jobs.hpfc" &&
        { TSAN_OPTIONS=halt_on_error=1:exitcode=66 $pack -q tests/data/invalid/nonplanar_crossing.pfc \
            -o "$t/bad.hpfc" 2>"$t/whole.err"; [ $? -eq 1 ]; } &&
        { TSAN_OPTIONS=halt_on_error=1:exitcode=66 $pack -q --partitions 8 --jobs 4 --root 4 \
            tests/data/invalid/nonplanar_crossing.pfc -o "$t/bad.hpfc" 2>"$t/jobs.err"; [ $? -eq 1 ]; } &&
        cmp "$t/whole.err" "$t/jobs.err" &&
        tsan_gis "$t"
    tsan_status=$?
    rm -rf "$t"
    return $tsan_status
}
if command -v clang >/dev/null 2>&1; then
    rm -rf build-tsan
    if CC=clang CXX=clang++ meson setup build-tsan -Db_sanitize=thread -Db_lundef=false \
            -Dcairo=disabled -Dpython=disabled -Dwerror=true >/dev/null &&
        ninja -C build-tsan tests/test_threads tests/test_faces_threads tests/test_build_threads \
            tests/test_faces_stream tests/test_sort tests/test_segnode tests/test_segment_graph hpfc-pack/hpfc-pack \
            >/dev/null &&
        TSAN_OPTIONS=halt_on_error=1:exitcode=66 build-tsan/tests/test_threads &&
        TSAN_OPTIONS=halt_on_error=1:exitcode=66 build-tsan/tests/test_sort &&
        TSAN_OPTIONS=halt_on_error=1:exitcode=66 build-tsan/tests/test_segnode &&
        TSAN_OPTIONS=halt_on_error=1:exitcode=66 build-tsan/tests/test_segment_graph &&
        TSAN_OPTIONS=halt_on_error=1:exitcode=66 build-tsan/tests/test_faces_threads 2 6 &&
        TSAN_OPTIONS=halt_on_error=1:exitcode=66 build-tsan/tests/test_faces_stream &&
        TSAN_OPTIONS=halt_on_error=1:exitcode=66 build-tsan/tests/test_build_threads 2 4 && tsan_pack; then
        echo "tsan: OK"
    else
        echo "tsan: FAILED"
        status=1
    fi
else
    echo "tsan: skipped (no clang)"
fi
# The Python package's pytest suite ran above, as the meson test
# python_pytest (suite `python`), under the sanitizers against build-test's
# package. tools/test-python.sh adds what only an installation shows: the
# package built without sanitizers, installed by meson and by pip, imports
# and answers.
sh tools/test-python.sh || { echo "python: FAILED"; status=1; }
python3 - build-test/meson-logs/testlog.json build-test/tests/pytest.xml <<'PY'
import json, os, sys
import xml.etree.ElementTree as ET
ok = bad = 0
for line in open(sys.argv[1]):
    r = json.loads(line)
    if r["name"].split(" / ")[-1] == "python_pytest":  # "hpfc:python / python_pytest"
        continue  # counted below, case by case (its status is in $status)
    if r["result"] in ("OK", "EXPECTEDFAIL"):
        ok += 1
    elif r["result"] != "SKIP":
        bad += 1
# pytest cases count one each; a missing report (pytest never ran: no
# python_pytest in build-test, or it was skipped) is a failure.
if os.path.exists(sys.argv[2]):
    for case in ET.parse(sys.argv[2]).iter("testcase"):
        tags = {child.tag for child in case}
        if tags & {"failure", "error"}:
            bad += 1
        elif "skipped" not in tags:
            ok += 1
else:
    bad += 1
print(f"tests: {ok} passed, {bad} failed")
PY
exit $status
