"""Point location: the numpy path against the scalar one, both against
hpfc-inspect --locate-batch (--lonlat), on packed and shipped files."""

import threading
from decimal import Decimal, ROUND_FLOOR

import numpy as np
import pytest

import hpfc
from hpfc import _hpfc
from conftest import VALID_HPFC, run_json_lines


def domain_points(f, n, seed, margin=0.05):
    """n random user-coordinate points over the domain and a bit around it,
    plus points on pixel corners of the deepest level (ties of the half-open
    cells)."""
    info = f.info
    scale = 10.0 ** info["unit_exp10"]
    rng = np.random.default_rng(seed)
    x0, y0, w, h = info["x0"], info["y0"], info["width"], info["height"]
    xs = rng.uniform(x0 - margin * w, x0 + (1 + margin) * w, n)
    ys = rng.uniform(y0 - margin * h, y0 + (1 + margin) * h, n)
    last = f.levels[-1]
    k = n // 4
    cx = x0 + rng.integers(0, w // last["cell_w"], k) * last["cell_w"]
    cy = y0 + rng.integers(0, h // last["cell_h"], k) * last["cell_h"]
    xs[:k], ys[:k] = cx * scale, cy * scale
    return xs * scale, ys * scale


def feature_of_cli(entry):
    return (entry["fid"], entry.get("key"), entry["layer"])


def check_scalar_against_batch(f, xs, ys, batch, lonlat=False):
    for k in range(len(xs)):
        one = f.locate_lonlat(xs[k], ys[k]) if lonlat else f.locate(xs[k], ys[k])
        assert bool(batch.inside[k]) == bool(one.inside), k
        assert batch.face_count[k] == len(one.faces), k
        assert batch.face[k] == (one.face if one.face is not None else -1), k
        assert batch.feature_count[k] == len(one.features), k
        assert batch.feature[k] == (one.feature if one.feature is not None else -1), k
        assert batch.key[k] == one.key, k
        assert bool(batch.exact[k]) == bool(one.exact and one.inside), k
        assert bool(batch.on_boundary[k]) == bool(one.on_boundary), k
        if one.feature is not None:  # the point's feature whichever candidate holds it
            assert all(f.face_features(face) == [one.feature] for face in one.faces), k
        if one.inside:
            assert (batch.x[k], batch.y[k]) == (one.x, one.y), k
            assert bool(batch.private[k]) == one.pixel.is_private, k
            assert batch.depth[k] == one.pixel.depth, k
            assert bool(batch.single[k]) == (len(one.faces) == 1), k
            assert one.exact == f.has_geometry, k
            if one.exact and not one.on_boundary:  # exact: one face, off the borders
                assert len(one.faces) == 1, k


def check_against_cli(f, inspect_tool, path, xs, ys, lonlat=False):
    text = "".join(f"{x!r},{y!r}\n" for x, y in zip(xs, ys))
    cmd = [inspect_tool, "--locate-batch", "-", str(path)]
    if lonlat:
        cmd.insert(3, "--lonlat")
    cli = run_json_lines(cmd, stdin=text)
    assert len(cli) == len(xs)
    for k, c in enumerate(cli):
        one = f.locate_lonlat(xs[k], ys[k]) if lonlat else f.locate(xs[k], ys[k])
        assert c["inside"] == one.inside, (k, c)
        assert c["faces"] == one.faces, (k, c)
        assert c["exact"] == f.has_geometry, (k, c)
        assert c["on_boundary"] == bool(one.on_boundary), (k, c)
        assert c.get("vertex") == one.vertex and c.get("edge") == one.edge, (k, c)
        assert [feature_of_cli(e) for e in c["features"]] == [
            (f.feature(i)["fid"], f.feature(i)["key"] if f.features_info["key_field"] else None,
             f.feature(i)["layer"]) for i in one.features], (k, c)
        if one.inside:
            assert c["pixel"] == str(one.pixel), (k, c)
            assert c["depth"] == one.pixel.depth
            assert c["private"] == one.pixel.is_private
            assert c["word"] == one.pixel.word


@pytest.mark.parametrize("which", ["delaunay", "polyline", "counties"])
def test_numpy_scalar_and_cli_agree(request, inspect_tool, which):
    path = request.getfixturevalue(which)
    with hpfc.open(path) as f:
        xs, ys = domain_points(f, 400, seed=len(which))
        batch = f.locate(xs, ys)
        assert batch.face.shape == xs.shape and batch.face.dtype == np.int64
        assert batch.inside.any() and (~batch.inside).any()
        check_scalar_against_batch(f, xs, ys, batch)
        check_against_cli(f, inspect_tool, path, xs[:150], ys[:150])


@pytest.mark.parametrize("path", VALID_HPFC, ids=lambda p: p.name)
def test_shipped_fixtures(inspect_tool, path):
    with hpfc.open(path) as f:
        xs, ys = domain_points(f, 80, seed=7)
        batch = f.locate(xs, ys)
        check_scalar_against_batch(f, xs, ys, batch)
        check_against_cli(f, inspect_tool, path, xs, ys)


def test_lonlat_against_cli(inspect_tool, counties):
    with hpfc.open(counties) as f:
        rng = np.random.default_rng(3)
        lon = rng.uniform(-80, -69.5, 300)
        lat = rng.uniform(37.5, 43.2, 300)
        batch = f.locate_lonlat(lon, lat)
        assert (batch.feature_count >= 1).sum() > 30  # the layer's counties are found
        assert (batch.feature >= 0).sum() > 10
        check_scalar_against_batch(f, lon, lat, batch, lonlat=True)
        check_against_cli(f, inspect_tool, counties, lon[:120], lat[:120], lonlat=True)
        # keys: the feature's key value where the answer is one feature
        keys = f.feature_keys()
        for k in np.flatnonzero(batch.feature >= 0)[:50]:
            assert batch.key[k] == keys[batch.feature[k]]


def test_lonlat_out_of_range(counties, delaunay):
    with hpfc.open(counties) as f:
        batch = f.locate_lonlat(np.array([0.0, 200.0, np.nan, -75.0]),
                                np.array([95.0, 0.0, 40.0, 41.0]))
        assert list(batch.inside[:3]) == [False, False, False]
        with pytest.raises(ValueError):
            f.locate_lonlat(200.0, 0.0)
    with hpfc.open(delaunay) as f:  # no CRS: no lon/lat, as the CLI says
        with pytest.raises(ValueError, match="no CRS"):
            f.locate_lonlat(1.0, 2.0)


def test_lattice_points_and_shapes(delaunay):
    with hpfc.open(delaunay) as f:
        info = f.info
        rng = np.random.default_rng(11)
        x = rng.integers(info["x0"] - 10, info["x0"] + info["width"] + 10, (20, 30))
        y = rng.integers(info["y0"] - 10, info["y0"] + info["height"] + 10, (20, 30))
        batch = f.locate_lattice(x, y)
        assert batch.face.shape == (20, 30)
        for i in range(0, 20, 3):
            for j in range(0, 30, 7):
                one = f.locate_lattice(int(x[i, j]), int(y[i, j]))
                assert batch.face_count[i, j] == len(one.faces)
                assert batch.face[i, j] == (one.face if one.face is not None else -1)
                px = f.leaf_at(int(x[i, j]), int(y[i, j]))
                assert (px is None) == (not one.inside)
                if px is not None:
                    x0, y0, x1, y1 = px.bounds
                    assert x0 <= x[i, j] < x1 and y0 <= y[i, j] < y1
        # broadcasting a scalar against an array
        b = f.locate_lattice(x[0], int(y[0, 0]))
        assert b.face.shape == (30,)
        # empty arrays
        e = f.locate(np.empty(0), np.empty(0))
        assert len(e) == 0


def test_private_leaves_have_one_face(delaunay):
    with hpfc.open(delaunay) as f:
        xs, ys = domain_points(f, 2000, seed=5, margin=0)
        b = f.locate(xs, ys)
        assert b.private.any()
        assert (b.face_count[b.private] == 1).all()
        assert (b.face[b.private] >= 0).all()
        assert (b.face[~b.inside] == -1).all() and (b.face_count[~b.inside] == 0).all()
        assert b.face.max() < f.face_count


def test_to_frame(counties):
    pd = pytest.importorskip("pandas")
    with hpfc.open(counties) as f:
        b = f.locate_lonlat(np.array([-75.0, -72.5]), np.array([41.0, 42.0]))
        frame = b.to_frame()
        assert isinstance(frame, pd.DataFrame)
        assert list(frame["face"]) == list(b.face)
        assert list(frame["key"]) == list(b.key)


def test_threads_share_a_file(delaunay):
    with hpfc.open(delaunay) as f:
        xs, ys = domain_points(f, 20000, seed=9)
        want = f.locate(xs, ys).face
        got = [None] * 4

        def work(k):
            got[k] = f.locate(xs, ys).face

        threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        for g in got:
            assert np.array_equal(g, want)


def decimal_floor(text, e):
    """The CLI's reading (hpfc-inspect views.c): None past |INT64_MAX|."""
    v = int((Decimal(text) / Decimal(10) ** e).to_integral_value(rounding=ROUND_FLOOR))
    return v if abs(v) <= 2**63 - 1 else None


@pytest.mark.parametrize("e", [-7, -6, -2, -1, 0, 1, 3])
def test_lattice_floor_reads_decimals_as_the_cli(e):
    """User coordinates are read as the decimal the user typed (repr), and
    projected ones as "%.17g": checked with Python's exact decimals on values
    at and next to lattice boundaries, where the double and the decimal
    straddle one."""
    rng = np.random.default_rng(100 + e)
    values = [0.3, -0.3, 0.1, 2.675, -1e-9, 0.0, -0.0, 123456.789, 1e15, -7.0, 9.2e18,
              -9.2e18, 9.3e18, 9.223372036854775e18, 1e-300, -1e-300, 5e-324]
    for k in rng.integers(-10**9, 10**9, 300):
        b = float(Decimal(int(k)) * Decimal(10) ** e)
        values += [b, np.nextafter(b, np.inf), np.nextafter(b, -np.inf)]
    values += list(rng.uniform(-1e6, 1e6, 300))
    for v in values:
        assert _hpfc.lattice_floor(v, e) == decimal_floor(repr(v), e), (v, e)
        assert _hpfc.lattice_floor(v, e, False) == decimal_floor("%.17g" % v, e), (v, e)
    assert _hpfc.lattice_floor(float("nan"), e) is None
    assert _hpfc.lattice_floor(float("inf"), e) is None
    assert _hpfc.lattice_floor(1e300, e) is None


def test_lattice_point_and_reprs(counties, delaunay):
    with hpfc.open(counties) as f:
        p = f.lattice_point(-75.0, 41.0, lonlat=True)
        one = f.locate_lonlat(-75.0, 41.0)
        assert p == (one.x, one.y)
        assert f.lattice_point(float("nan"), 0.0) is None
        assert "Location(" in repr(one) and str(one.pixel) in repr(one)
        assert repr(one.pixel).startswith("<hpfc.Pixel ")
        assert "hpfc.File" in repr(f)
    assert "closed" in repr(f)
    with hpfc.open(delaunay) as f:
        e = f.unit_exp10
        for v in (0.5, -3.25, 1234.0):
            assert f.lattice_point(v, v) == (_hpfc.lattice_floor(v, e),) * 2
        info = f.info
        cx = (info["x0"] + info["width"] // 2) * 10.0 ** e
        cy = (info["y0"] + info["height"] // 2) * 10.0 ** e
        one = f.locate(cx, cy)
        assert one.inside
        assert len(one.pixel.path) == one.pixel.depth + 1
        assert str(one.pixel) == "/".join(f"{i},{j}" for i, j in one.pixel.path)


def read_pfc(path):
    """The vertices and straight edges of a .pfc file (unit 0)."""
    vertices, edges = [], []
    for line in open(path):
        part = line.split()
        if part and part[0] == "v":
            vertices.append((int(part[1]), int(part[2])))
        elif part and part[0] == "e" and len(part) == 3:
            edges.append((int(part[1]), int(part[2])))
    return vertices, edges


def test_exact_boundary_points(delaunay):
    """On a file with exact geometry every input vertex is on the boundary
    (that very vertex), every lattice midpoint of an edge on that edge, the
    numpy path agreeing with the scalar one."""
    from conftest import DATA

    vertices, edges = read_pfc(DATA / "delaunay-4000.pfc")
    with hpfc.open(delaunay) as f:
        if not f.has_geometry:
            pytest.skip("packed without exact geometry")
        for v, (x, y) in enumerate(vertices[:300]):
            one = f.locate_lattice(x, y)
            assert one.on_boundary and one.vertex == v and one.edge is None, (v, one)
            assert len(one.faces) >= 1 and one.face == (one.faces[0] if len(one.faces) == 1 else None)
        mids = [(e, (vertices[u][0] + vertices[w][0]) // 2, (vertices[u][1] + vertices[w][1]) // 2)
                for e, (u, w) in enumerate(edges[:2000])
                if (vertices[u][0] + vertices[w][0]) % 2 == 0 and (vertices[u][1] + vertices[w][1]) % 2 == 0]
        assert len(mids) > 50
        xs = np.array([m[1] for m in mids]), np.array([m[2] for m in mids])
        batch = f.locate_lattice(*xs)
        assert batch.on_boundary.all() and batch.exact.all()
        for k, (e, x, y) in enumerate(mids):
            one = f.locate_lattice(x, y)
            assert one.on_boundary and one.edge == e and one.vertex is None, (e, one)
            assert batch.face_count[k] == len(one.faces) and 1 <= len(one.faces) <= 2
            # a point next to it, off the edge, lies in one of the edge's faces
            near = f.locate_lattice(x + 1, y)
            assert near.on_boundary or (len(near.faces) == 1)
