#!/bin/sh
# Checks the Python package (python/) as users install it, with Debian's
# /usr/bin/python3 (not whatever python3 comes first on PATH): builds it
# without sanitizers in build-python (an extension linked with ASan cannot
# load into an interpreter started without the ASan runtime), installs it
# the two ways, `meson install` into a staging directory and
# `pip install --no-build-isolation .` (meson-python) into a venv, and checks
# that each imports and answers from where it was installed.
#
# The pytest suite itself (python/tests) is not run here: it is the meson
# test python_pytest (suite `python`), which tools/run-tests.sh runs in its
# sanitized build against the package that build made. Running it here too
# would repeat the same tests on the same code without the sanitizers.
# Usage: sh tools/test-python.sh
set -eu
cd "$(dirname "$0")/.."
PY=/usr/bin/python3
rm -rf build-python
if ! "$PY" -c 'import numpy' 2>/dev/null; then
    echo "python: $PY has no numpy (tools/install-deps.sh installs it)" >&2
    exit 1
fi
meson setup build-python -Dpython_only=true -Dpython=enabled -Dwerror=true >/dev/null
ninja -C build-python >/dev/null
fixture=$(realpath tests/data/valid/borders_features.hpfc)

# answers HOW WHERE [ENV=VALUE...] PYTHON: PYTHON imports hpfc from a path
# containing WHERE (not from this checkout or another installation), and
# it answers a location on a fixture.
answers() {
    how=$1 where=$2
    shift 2
    (cd build-python && env "$@" - "$where" "$fixture") <<'PY' || { echo "python: $how: FAILED" >&2; exit 1; }
import sys
import hpfc
assert sys.argv[1] in hpfc.__file__, hpfc.__file__
with hpfc.open(sys.argv[2]) as f:
    loc = f.locate(1, 1)
    assert loc.inside and loc.faces == [0, 1, 2], loc
PY
    echo "python: $how package imports and answers"
}

# The first way in: meson install into a staging directory.
meson install -C build-python --destdir "$PWD/build-python/stage" >/dev/null
site=$(dirname "$(dirname "$(find "$PWD/build-python/stage" -path '*/hpfc/__init__.py')")")
answers "meson-installed" /build-python/stage/ PYTHONPATH="$site" "$PY"

# The second way in: pip through meson-python, offline, into a venv that
# sees Debian's numpy.
"$PY" -m venv --system-site-packages build-python/venv
build-python/venv/bin/pip install -q --no-build-isolation --no-index --no-deps . \
    >build-python/pip.log 2>&1 || { cat build-python/pip.log >&2; echo "python: pip install failed" >&2; exit 1; }
answers "pip-installed" /build-python/venv/ venv/bin/python
