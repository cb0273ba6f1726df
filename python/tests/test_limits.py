"""File.set_limits and File.limits: the library's caps on one geometry or
topology call (hpfc_shapes_set_limits) from Python.

Oracles: the same call on the same file with the caps lifted (the geometry
and the window must come back equal once a cap is raised), and the
window's own answer, whose faces + edges + features are exactly what
max_items counts (hpfc.h): that many passes, one fewer raises.
"""

import pytest

np = pytest.importorskip("numpy")

import hpfc  # noqa: E402

OVER_LIMIT = 51  # HPFC_E_OVER_LIMIT, pinned in hpfc.h and the spec


def _biggest_feature(f):
    """The feature whose geometry has the most points, and that many."""
    sizes = [len(f.feature_arrays([k]).xy) for k in range(f.features_info["features"])]
    k = int(np.argmax(sizes))
    return k, sizes[k]


def _same_arrays(a, b):
    return (np.array_equal(a.xy, b.xy) and np.array_equal(a.ring_offsets, b.ring_offsets)
            and np.array_equal(a.polygon_offsets, b.polygon_offsets)
            and np.array_equal(a.part_offsets, b.part_offsets))


def _everything(f):
    """The window over the whole domain (lattice integers)."""
    d = f.info
    return f.window(d["x0"], d["y0"], d["x0"] + d["width"], d["y0"] + d["height"], lattice=True)


def test_defaults_and_reading_back(counties):
    with hpfc.open(counties) as f:
        assert f.limits == {"max_points": hpfc.LIMIT_POINTS_DEFAULT,
                            "max_items": hpfc.LIMIT_ITEMS_DEFAULT}
        assert hpfc.LIMIT_POINTS_DEFAULT == 2**23 and hpfc.LIMIT_ITEMS_DEFAULT == 2**24
        assert hpfc.LIMIT_NONE == 2**64 - 1
        f.set_limits(max_points=100)
        assert f.limits == {"max_points": 100, "max_items": hpfc.LIMIT_ITEMS_DEFAULT}
        # each call sets both: what is left out goes back to its default
        f.set_limits(max_items=hpfc.LIMIT_NONE)
        assert f.limits == {"max_points": hpfc.LIMIT_POINTS_DEFAULT,
                            "max_items": hpfc.LIMIT_NONE}
        f.limits["max_points"] = 1  # a copy: changing it changes nothing
        assert f.limits["max_points"] == hpfc.LIMIT_POINTS_DEFAULT


def test_max_points_refuses_a_big_feature_then_lets_it_through(counties):
    with hpfc.open(counties) as unlimited:
        unlimited.set_limits(max_points=hpfc.LIMIT_NONE)
        big, points = _biggest_feature(unlimited)
        expected = unlimited.feature_arrays([big])
    with hpfc.open(counties) as f:
        f.set_limits(max_points=points // 2)  # before the index exists
        with pytest.raises(hpfc.Error) as e:
            f.feature_arrays([big])
        assert e.value.code == OVER_LIMIT and e.value.name == "HPFC_E_OVER_LIMIT"
        assert f"feature {big}" in str(e.value) and "set_limits" in str(e.value)
        f.set_limits(max_points=4 * points)  # the index exists now
        assert _same_arrays(f.feature_arrays([big]), expected)
        f.set_limits(max_points=points // 2)
        with pytest.raises(hpfc.Error) as e:
            f.feature_arrays([big])
        assert e.value.code == OVER_LIMIT
        f.set_limits()  # the defaults: far above this file
        assert _same_arrays(f.feature_arrays([big]), expected)


def test_max_points_through_shapely(counties):
    pytest.importorskip("shapely")
    with hpfc.open(counties) as f:
        f.set_limits(max_points=hpfc.LIMIT_NONE)
        big, points = _biggest_feature(f)
        expected = f.feature_geometry(big)
        f.set_limits(max_points=points // 2)
        with pytest.raises(hpfc.Error) as e:
            f.feature_geometry(big)
        assert e.value.code == OVER_LIMIT
        f.set_limits(max_points=4 * points)
        got = f.feature_geometry(big)
        assert got.wkb == expected.wkb


def test_max_items_refuses_a_window(counties):
    with hpfc.open(counties) as f:
        f.set_limits(max_items=hpfc.LIMIT_NONE)
        expected = _everything(f)
        items = sum(len(expected[k]) for k in ("faces", "edges", "features"))
        assert items > 2
        f.set_limits(max_items=items - 1)
        with pytest.raises(hpfc.Error) as e:
            _everything(f)
        assert e.value.code == OVER_LIMIT and "window" in str(e.value)
        f.set_limits(max_items=items)
        got = _everything(f)
        assert set(got) == set(expected)
        for k in expected:
            assert np.array_equal(got[k], expected[k]), k
        # max_items does not cap geometry, nor max_points windows
        f.set_limits(max_items=1)
        f.feature_arrays([0])
        f.set_limits(max_points=1)
        _everything(f)


def test_wrong_limits(counties):
    with hpfc.open(counties) as f:
        for bad in (0, -1, hpfc.LIMIT_NONE + 1):
            with pytest.raises(ValueError, match="max_points"):
                f.set_limits(max_points=bad)
        for bad in (1.5, "10", True):
            with pytest.raises(TypeError, match="max_items"):
                f.set_limits(max_items=bad)
        assert f.limits["max_points"] == hpfc.LIMIT_POINTS_DEFAULT  # unchanged by a refusal
        f.set_limits(max_points=np.uint64(7))
        assert f.limits["max_points"] == 7 and type(f.limits["max_points"]) is int
