"""Features and their attributes against the GIS layer they were packed from
and against hpfc-inspect."""

import json

import pytest

import hpfc
from conftest import TESTS_DATA, run_json_lines


def test_features_are_the_layers_polygons(counties):
    layer = json.load(open(TESTS_DATA / "gis" / "counties_ne.geojson"))
    names = [feat["properties"]["name"] for feat in layer["features"]]
    with hpfc.open(counties) as f:
        info = f.features_info
        assert info["features"] == len(names) and info["key_field"] == "name"
        assert info["faces"] == f.face_count
        feats = f.features()
        assert [d["key"] for d in feats] == names  # fid = position in the layer
        assert [d["fid"] for d in feats] == list(range(len(names)))
        assert {d["layer"] for d in feats} == {f.layer_name(0)}
        assert f.feature(3) == feats[3]
        assert f.feature_keys() == names
        # every feature covers at least one face, every link is a feature
        linked = set()
        for face in range(f.face_count):
            fs = f.face_features(face)
            assert fs == sorted(fs) and all(0 <= k < len(names) for k in fs)
            linked.update(fs)
        assert linked == set(range(len(names)))
        assert f.face_features(0) == []  # the unbounded face lies in no county
        with pytest.raises(hpfc.Error) as e:
            f.face_features(f.face_count)
        assert e.value.name == "HPFC_E_ARG"
        with pytest.raises(hpfc.Error):
            f.feature(len(names))
        with pytest.raises(IndexError):
            f.feature(2**40)


def test_features_frame(counties):
    pd = pytest.importorskip("pandas")
    with hpfc.open(counties) as f:
        frame = f.features_frame()
        assert isinstance(frame, pd.DataFrame)
        assert list(frame.columns) == ["fid", "layer", "name"]
        assert len(frame) == f.features_info["features"]
        assert frame.loc[5, "name"] == f.feature(5)["key"]


def test_features_of_a_shipped_fixture_match_cli(inspect_tool):
    path = TESTS_DATA / "valid" / "borders_features.hpfc"
    with hpfc.open(path) as f:
        assert f.has_features
        # the CLI lists (fid, key, layer) of the faces of a point's leaf
        for x, y in ((1, 1), (0.5, -0.5), (-1, 2)):
            (cli,) = run_json_lines([inspect_tool, "--locate", f"{x},{y}", "--json", str(path)])
            one = f.locate(x, y)
            assert cli["features"] == [{"fid": f.feature(k)["fid"], "key": f.feature(k)["key"],
                                        "layer": f.feature(k)["layer"]} for k in one.features]


def test_file_without_features(delaunay):
    with hpfc.open(delaunay) as f:
        assert f.features_info is None and not f.has_features
        assert f.features() == [] and f.feature_keys() == []
        with pytest.raises(hpfc.Error) as e:
            f.feature(0)
        assert e.value.name == "HPFC_E_NO_SECTION" and e.value.code == 50
        b = f.locate(*[[v] for v in (f.info["x0"] * 10.0 ** f.unit_exp10,) * 2])
        assert b.feature[0] == -1 and b.key[0] is None
