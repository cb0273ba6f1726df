"""Opening, the header, the level table, the sections and the CRS, against
hpfc-inspect --json on the same files."""

import json
import pathlib
import re
import subprocess

import pytest

import hpfc
from hpfc import _hpfc
from conftest import VALID_HPFC


def cli_info(inspect_tool, path):
    r = subprocess.run([inspect_tool, "--json", str(path)], capture_output=True, text=True,
                       check=True)
    return json.loads(r.stdout)


def check_against_cli(f, c):
    info = f.info
    assert info["format_version"] == (c["format_major"], c["format_minor"])
    assert (info["root_cols"], info["root_rows"]) == (c["root_cols"], c["root_rows"])
    assert (info["cols"], info["rows"]) == (c["refine_cols"], c["refine_rows"])
    assert info["levels"] == c["level_count"]
    dom = c["domain"]
    assert (info["x0"], info["y0"], info["width"], info["height"]) == (
        dom["x0"], dom["y0"], dom["width"], dom["height"])
    assert info["unit_exp10"] == c["unit_exp10"]
    assert info["file_size"] == c["file_bytes"]
    assert f.crs == c.get("crs")
    assert f.levels == c["levels"]
    assert [{k: s[k] for k in ("tag", "flags", "offset", "length", "crc32c")}
            for s in f.sections] == c["sections"]
    assert sum(l["word_pixels"] for l in f.levels) == c["word_pixels"]


@pytest.mark.parametrize("path", VALID_HPFC, ids=lambda p: p.name)
def test_shipped_fixtures_match_cli(inspect_tool, path):
    with hpfc.open(path) as f:
        check_against_cli(f, cli_info(inspect_tool, path))
        f.verify_checksums()


def test_packed_files_match_cli(inspect_tool, delaunay, counties):
    for path in (delaunay, counties):
        with hpfc.open(str(path)) as f:
            check_against_cli(f, cli_info(inspect_tool, path))


def test_context_manager_and_close(delaunay):
    with hpfc.open(delaunay) as f:
        assert not f.closed
        assert f.info["levels"] >= 1
    assert f.closed
    with pytest.raises(ValueError):
        f.info
    with pytest.raises(ValueError):
        f.locate(0.0, 0.0)
    f.close()  # twice is fine
    g = hpfc.open(str(delaunay))
    px = g.root(0, 0)
    g.close()
    with pytest.raises(ValueError):
        px.word  # a pixel of a closed file fails cleanly


def test_path_types(delaunay):
    import pathlib

    for p in (str(delaunay), pathlib.Path(delaunay), str(delaunay).encode()):
        with hpfc.open(p) as f:
            assert f.info["file_size"] == pathlib.Path(delaunay).stat().st_size


def test_crs_of_packed_gis_layer(counties):
    with hpfc.open(counties) as f:
        assert f.crs is not None and "+proj=" in f.crs
        assert f.unit_exp10 == f.info["unit_exp10"]


def test_version_and_strerror():
    assert hpfc.library_version.count(".") == 2
    assert hpfc.strerror(0) != hpfc.strerror(48)
    assert isinstance(hpfc.strerror(12345), str)


def test_status_names_follow_the_spec_table():
    """Every code of spec §7.4 has the spec's name in hpfc.Error and a text
    of its own; HPFC_E_BUFFER_SMALL (4) is one of them."""
    spec = pathlib.Path(__file__).resolve().parents[2] / "spec" / "hpfc-format.md"
    table = spec.read_text().split("### 7.4 Status codes")[1].split("\n## ")[0]
    rows = re.findall(r"^\| (\d+) \| `(HPFC_[A-Z_]+)` \|", table, re.M)
    assert ("4", "HPFC_E_BUFFER_SMALL") in rows
    unknown = hpfc.strerror(12345)
    for number, name in rows:
        assert _hpfc.status_name(int(number)) == name
        assert hpfc.strerror(int(number)) != unknown
