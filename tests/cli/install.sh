#!/bin/sh
# `meson install`: installs the library, its header, the two tools and
# the GDAL plugin, nothing of the tests, fuzzers or benchmarks; the benchmarks
# and libFuzzer binaries are not built by default at all, and -Dtests=false
# configures the library and the tools only. The installed tools carry a
# RUNPATH to the installed library's directory, so that they run from any
# --prefix without LD_LIBRARY_PATH. The build directory is the one the
# tested hpfc-pack lives in; installing copies its files (--no-rebuild)
# into a temporary DESTDIR.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
build=$(cd "$(dirname "$PACK_BIN")/.." && pwd)
src=$(cd "$TESTS/.." && pwd)
if ! command -v meson >/dev/null || [ ! -f "$build/meson-info/intro-targets.json" ]; then
    echo "no meson build directory around $PACK_BIN: skipped"
    exit 77
fi

# what ninja builds by default, from meson's own introspection
python3 - "$build/meson-info/intro-targets.json" <<'PY' || fail "default targets"
import json, sys
targets = json.load(open(sys.argv[1]))
bad = [t["name"] for t in targets
       if (t["name"].startswith(("bench_", "fuzz_")) and t["build_by_default"]) or
          (t["name"].startswith(("bench_", "fuzz_", "replay_", "test_")) and t["installed"])]
assert not bad, f"built by default or installed: {bad}"
installed = {t["name"] for t in targets if t["installed"]}
assert {"hpfc-pack", "hpfc-inspect", "hpfcfile"} <= installed, installed
PY

# a real install into DESTDIR, of the files already built
run meson install -C "$build" --no-rebuild --destdir "$tmp/dest"
[ "$rc" -eq 0 ] || fail "meson install: exit $rc: $(tail -3 "$tmp/err")"
prefix=$(python3 -c 'import json,sys; print({o["name"]: o["value"] for o in json.load(open(sys.argv[1]))}["prefix"])' \
    "$build/meson-info/intro-buildoptions.json")
libdir=$(python3 -c 'import json,sys; print({o["name"]: o["value"] for o in json.load(open(sys.argv[1]))}["libdir"])' \
    "$build/meson-info/intro-buildoptions.json")
case $libdir in /*) ;; *) libdir=$prefix/$libdir ;; esac
for tool in hpfc-pack hpfc-inspect; do
    bin=$tmp/dest$prefix/bin/$tool
    [ -x "$bin" ] || { fail "$tool not installed in $prefix/bin"; continue; }
    if command -v readelf >/dev/null; then
        readelf -d "$bin" | grep -E "RUNPATH|RPATH" | grep -qF "$libdir" ||
            fail "$tool: no RUNPATH to $libdir: $(readelf -d "$bin" | grep -E 'RUNPATH|RPATH')"
    fi
done
[ -f "$tmp/dest$prefix/include/hpfc.h" ] || fail "hpfc.h not installed"
extra=$(find "$tmp/dest" -type f -name 'bench_*' -o -type f -name 'replay_*' -o -type f -name 'fuzz_*' \
    -o -type f -name 'test_*' -o -type f -name 'gen-*')
[ -n "$extra" ] && fail "installed: $extra"
[ -n "$(find "$tmp/dest$libdir" -name 'libhpfcfile.so*')" ] || fail "libhpfcfile not in $libdir"
# the GDAL plugin, where built: in LIBDIR/gdalplugins, the library linked
# into it (no libhpfcfile or GeographicLib to find at load, no RUNPATH), only
# GDAL's entry points exported, and found there by GDAL_DRIVER_PATH alone
if [ -f "$build/gdal/ogr_HPFC.so" ]; then
    plugin=$tmp/dest$libdir/gdalplugins/ogr_HPFC.so
    if [ ! -f "$plugin" ]; then
        fail "ogr_HPFC.so not installed in $libdir/gdalplugins"
    else
        if command -v readelf >/dev/null; then
            needed=$(readelf -d "$plugin" | grep NEEDED)
            case $needed in
            *libhpfcfile* | *GeographicLib*) fail "ogr_HPFC.so needs a library linked into it: $needed" ;;
            esac
            exported=$(readelf -W --dyn-syms "$plugin" | awk '$7 != "UND" && $5 == "GLOBAL" && $4 == "FUNC" {print $8}' |
                sort | tr '\n' ' ')
            [ "$exported" = "GDALRegisterMe RegisterOGRHPFC " ] ||
                fail "ogr_HPFC.so exports more than GDAL's entry points: $exported"
        fi
        # (a sanitized plugin loads only into a process with the runtime
        # preloaded: tests/cli/gdal_driver.sh covers that build)
        if command -v ogrinfo >/dev/null && ! ldd "$plugin" 2>/dev/null | grep -q 'libasan\|libubsan'; then
            run env GDAL_DRIVER_PATH="$tmp/dest$libdir/gdalplugins" ogrinfo --formats
            grep -q "HPFC -vector-" "$tmp/out" || fail "the installed plugin is not found: $(cat "$tmp/err")"
        fi
    fi
fi

# -Dtests=false: the library and the tools, no test, fuzz or bench target
if meson setup "$tmp/b" "$src" -Dtests=false >"$tmp/setup.log" 2>&1; then
    python3 - "$tmp/b/meson-info/intro-targets.json" <<'PY' || fail "-Dtests=false still has dev targets"
import json, sys
names = sorted(t["name"] for t in json.load(open(sys.argv[1])))
dev = [n for n in names if n.startswith(("bench_", "fuzz_", "replay_", "test_", "gen-"))]
assert not dev and "hpfc-pack" in names and "hpfc-inspect" in names, names
PY
else
    fail "meson setup -Dtests=false: $(tail -3 "$tmp/setup.log")"
fi

finish
