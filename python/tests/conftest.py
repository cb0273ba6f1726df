"""Shared fixtures: the repository's data, the command-line tools, packed files.

The tools (hpfc-pack, hpfc-inspect) are the oracle the package is compared
with. They come from HPFC_PACK / HPFC_INSPECT (tools/run-tests.sh sets both)
or from a build directory of this checkout; without them the comparisons
skip, unless HPFC_REQUIRE_TOOLS=1 (as in tools/run-tests.sh), where they fail.
"""

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "data"
TESTS_DATA = ROOT / "tests" / "data"


def _find_tool(env, subdir, name):
    if os.environ.get(env):
        return os.environ[env]
    for build in sorted(ROOT.glob("build*")):
        cand = build / subdir / name
        if cand.is_file() and os.access(cand, os.X_OK):
            return str(cand)
    return shutil.which(name)


def _need(tool, what):
    if tool:
        return tool
    if os.environ.get("HPFC_REQUIRE_TOOLS") == "1":
        pytest.fail(f"{what} not found (set HPFC_PACK / HPFC_INSPECT)")
    pytest.skip(f"{what} not found")


@pytest.fixture(scope="session")
def inspect_tool():
    return _need(_find_tool("HPFC_INSPECT", "hpfc-inspect", "hpfc-inspect"), "hpfc-inspect")


@pytest.fixture(scope="session")
def pack_tool():
    return _need(_find_tool("HPFC_PACK", "hpfc-pack", "hpfc-pack"), "hpfc-pack")


def run_json_lines(cmd, stdin=None):
    """Runs a tool, returns its stdout's JSON objects (one a line)."""
    r = subprocess.run(cmd, input=stdin, capture_output=True, text=True, check=False)
    assert r.returncode == 0, f"{cmd}: exit {r.returncode}: {r.stderr}"
    return [json.loads(line) for line in r.stdout.splitlines() if line.strip()]


@pytest.fixture(scope="session")
def packed(tmp_path_factory, pack_tool):
    """Packs an input once per session: packed(name, input, *options) -> path."""
    out_dir = tmp_path_factory.mktemp("packed")
    cache = {}

    def make(name, source, *options):
        if name not in cache:
            out = out_dir / f"{name}.hpfc"
            r = subprocess.run([pack_tool, *options, "--quiet", str(source), "-o", str(out)],
                               capture_output=True, text=True, check=False)
            if r.returncode != 0 and "not built in" in r.stderr:
                pytest.skip(f"hpfc-pack: {r.stderr.strip()}")
            assert r.returncode == 0, r.stderr
            cache[name] = out
        return cache[name]

    return make


@pytest.fixture(scope="session")
def delaunay(packed):
    """data/delaunay-4000.pfc packed with default options (no features)."""
    return packed("delaunay", DATA / "delaunay-4000.pfc")


@pytest.fixture(scope="session")
def polyline(packed):
    return packed("polyline", DATA / "polyline-3000.pfc")


@pytest.fixture(scope="session")
def counties(packed):
    """The counties fixture (54 polygons, GIS input): CRS and features."""
    return packed("counties", TESTS_DATA / "gis" / "counties_ne.geojson", "--invalid", "node",
                  "--key", "name")


VALID_HPFC = sorted((TESTS_DATA / "valid").glob("*.hpfc"))


def expected_invalid():
    """(path, code name) of the damaged .hpfc fixtures (tests/data/invalid/EXPECTED)."""
    out = []
    for line in (TESTS_DATA / "invalid" / "EXPECTED").read_text().splitlines():
        parts = line.split()
        if len(parts) == 2 and parts[0].endswith(".hpfc"):
            out.append((TESTS_DATA / "invalid" / parts[0], parts[1]))
    return out
