#!/bin/sh
# Tests the Python package (python/) with Debian's /usr/bin/python3
# (not whatever python3 comes first on PATH): builds it without sanitizers in
# build-python (an extension linked with ASan cannot load into an interpreter
# started without the ASan runtime), installs it by `meson install` into a
# staging directory and runs pytest on python/tests, with PACK and INSPECT
# (the sanitized tools of the main build) as the oracle; then installs it
# the second way, `pip install --no-build-isolation .` (meson-python) into a
# venv, and checks that it imports and answers. pytest's report goes to
# build-python/pytest.xml (tools/run-tests.sh counts it).
# Usage: sh tools/test-python.sh PACK INSPECT
set -eu
cd "$(dirname "$0")/.."
PY=/usr/bin/python3
pack=$(realpath "$1")
inspect=$(realpath "$2")
rm -rf build-python
if ! "$PY" -c 'import numpy, pytest' 2>/dev/null; then
    echo "python: $PY has no numpy or pytest (tools/install-deps.sh installs them)" >&2
    exit 1
fi
meson setup build-python -Dpython_only=true -Dpython=enabled -Dwerror=true >/dev/null
ninja -C build-python >/dev/null
meson install -C build-python --destdir "$PWD/build-python/stage" >/dev/null
site=$(dirname "$(dirname "$(find "$PWD/build-python/stage" -path '*/hpfc/__init__.py')")")
status=0
HPFC_PACK=$pack HPFC_INSPECT=$inspect HPFC_REQUIRE_TOOLS=1 PYTHONPATH=$site \
    "$PY" -m pytest -q -p no:cacheprovider --junitxml=build-python/pytest.xml python/tests ||
    status=$?
# pytest exits 5 when it collected no test: that is a failure too.
[ "$status" -eq 0 ] || { echo "python: pytest exited $status" >&2; exit 1; }

# The second way in: pip through meson-python, offline, into a venv that
# sees Debian's numpy.
"$PY" -m venv --system-site-packages build-python/venv
build-python/venv/bin/pip install -q --no-build-isolation --no-index --no-deps . \
    >build-python/pip.log 2>&1 || { cat build-python/pip.log >&2; echo "python: pip install failed" >&2; exit 1; }
(cd build-python && venv/bin/python - "$(realpath ../tests/data/valid/borders_features.hpfc)") <<'PY'
import sys
import hpfc
assert "venv" in hpfc.__file__, hpfc.__file__
with hpfc.open(sys.argv[1]) as f:
    loc = f.locate(1, 1)
    assert loc.inside and loc.faces == [0, 1, 2], loc
print("python: pip-installed package imports and answers")
PY
