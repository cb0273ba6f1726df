"""The topology questions (File.window, neighbours, adjacency, nearest,
edges_within, dissolve, mesh) against shapely/GEOS on the layers' own
geometry: a coverage with a hole, an enclave, a multipolygon, cells that
touch at one vertex only and an island, plus a line layer, packed by
hpfc-pack with --projection none (the lattice is the input's integers).

Oracles: `intersects` / `covers` for the window, `touches` and the length
of the boundaries' intersection for neighbours, the distance to every
boundary for nearest, `unary_union` per group for dissolve (same area,
Hausdorff distance within half a lattice unit), and the boundaries'
lengths for the mesh.
"""

import json
import random

import pytest

np = pytest.importorskip("numpy")
shapely = pytest.importorskip("shapely")
from shapely.geometry import LineString, MultiLineString, Point, Polygon, box, shape  # noqa: E402
from shapely.ops import unary_union  # noqa: E402

import hpfc  # noqa: E402

O = 1000  # an offset that keeps the coordinates out of the lon/lat range


def _cell(i, j, s=10):
    """Cell (i, j) with a shape point in the middle of each side, so that
    borders are polylines, not single segments."""
    x, y = O + i * s, O + j * s
    h = s // 2
    return Polygon([(x, y), (x + h, y), (x + s, y), (x + s, y + h), (x + s, y + s),
                    (x + h, y + s), (x, y + s), (x, y + h)])


# Feature name -> cells. "ring" surrounds "enclave" (a hole); "multi" has
# two parts; "diag_a" / "diag_b" touch at one vertex only; "island" lies
# apart; the rest fill a coverage.
LAYOUT = {
    "ring": [(1, 1), (2, 1), (3, 1), (1, 2), (3, 2), (1, 3), (2, 3), (3, 3)],
    "enclave": [(2, 2)],
    "multi": [(0, 0), (4, 4)],
    "west": [(0, 1), (0, 2), (0, 3), (0, 4)],
    "south": [(1, 0), (2, 0), (3, 0), (4, 0)],
    "east": [(4, 1), (4, 2), (4, 3)],
    "north": [(1, 4), (2, 4), (3, 4)],
    "diag_a": [(6, 0)],
    "diag_b": [(7, 1)],
    "island": [(9, 9)],
}
GROUP = {"ring": "a", "enclave": "b", "multi": "a", "west": "b", "south": "c", "east": "c",
         "north": "a", "diag_a": "b", "diag_b": "b", "island": None}


def _geometries():
    return {name: unary_union([_cell(i, j) for i, j in cells]) for name, cells in LAYOUT.items()}


LINES = {
    "l1": LineString([(O, O), (O + 10, O + 5), (O + 20, O)]),
    "l2": LineString([(O + 20, O), (O + 30, O + 10)]),          # meets l1 at its end
    "l3": LineString([(O + 10, O + 20), (O + 10, O + 5)]),      # ends on l1's shape point
    "l4": LineString([(O + 40, O + 40), (O + 50, O + 45)]),     # alone
}


def _write(path, geoms, props):
    features = [{"type": "Feature", "properties": props[name],
                 "geometry": json.loads(json.dumps(g.__geo_interface__))}
                for name, g in geoms.items()]
    path.write_text(json.dumps({"type": "FeatureCollection", "features": features}))


@pytest.fixture(scope="module")
def coverage(tmp_path_factory, packed):
    d = tmp_path_factory.mktemp("topology")
    geoms = _geometries()
    _write(d / "coverage.geojson", geoms,
           {n: {"name": n, "grp": GROUP[n]} for n in geoms})
    path = packed("topology_coverage", d / "coverage.geojson", "--projection", "none", "-a_srs", "EPSG:3857",
                  "--key", "name", "--fields", "all")
    f = hpfc.open(path)
    keys = f.feature_keys()
    yield f, {k: geoms[k] for k in keys}, keys
    f.close()


@pytest.fixture(scope="module")
def lines(tmp_path_factory, packed):
    d = tmp_path_factory.mktemp("topology_lines")
    _write(d / "lines.geojson", LINES, {n: {"name": n} for n in LINES})
    # every shape point a vertex: where one line ends and the next begins
    # (l1, l2) is a point of degree 2, which the default vertex model would
    # not make a vertex, and EDGF would then link one edge to both lines
    path = packed("topology_lines", d / "lines.geojson", "--projection", "none", "-a_srs",
                  "EPSG:3857", "--key", "name", "--vertices", "all")
    f = hpfc.open(path)
    keys = f.feature_keys()
    yield f, {k: LINES[k] for k in keys}, keys
    f.close()


def _boundary(g):
    return g.boundary if g.geom_type in ("Polygon", "MultiPolygon") else g


# ---- window -------------------------------------------------------------------------

def test_window_matches_intersects(coverage):
    f, geoms, keys = coverage
    rng = random.Random(5)
    for _ in range(60):
        x0, y0 = rng.uniform(O - 10, O + 100), rng.uniform(O - 10, O + 100)
        x1, y1 = x0 + rng.choice([0, 1, 5, 17, 40]), y0 + rng.choice([0, 3, 12, 60])
        x0, y0, x1, y1 = (float(int(v)) for v in (x0, y0, x1, y1))
        w = f.window(x0, y0, x1, y1)
        # GEOS wants a degenerate window as what it is: a point or a segment
        win = (Point(x0, y0) if (x0, y0) == (x1, y1) else
               LineString([(x0, y0), (x1, y1)]) if x0 == x1 or y0 == y1 else box(x0, y0, x1, y1))
        want = {k for k, name in enumerate(keys) if geoms[name].intersects(win)}
        got = set(w["features"].tolist())
        assert got == want, (x0, y0, x1, y1)
        for k, inside in zip(w["features"].tolist(), w["features_inside"].tolist()):
            assert inside == win.covers(geoms[keys[k]]), (keys[k], x0, y0, x1, y1)


# ---- neighbours ----------------------------------------------------------------------

def _oracle_touch(a, b):
    """("edge", length) / ("vertex", 0) / None from the boundaries."""
    shared = _boundary(a).intersection(_boundary(b))
    if shared.is_empty:
        return None
    if shared.length > 0:
        return ("edge", shared.length)
    return ("vertex", 0.0)


def _check_neighbours(f, geoms, keys):
    pairs = 0
    for k, name in enumerate(keys):
        nb = f.neighbours(name)
        got = {int(j): (t, length) for j, t, length in
               zip(nb["feature"], nb["touch"], nb["length"])}
        for j, other in enumerate(keys):
            if j == k:
                continue
            want = _oracle_touch(geoms[name], geoms[other])
            if want is None:
                assert j not in got, (name, other)
                continue
            pairs += 1
            assert j in got, (name, other, want)
            assert got[j][0] == want[0], (name, other)
            assert got[j][1] == pytest.approx(want[1], rel=1e-12, abs=1e-9)
            if geoms[name].geom_type != "LineString":
                # the coverage's features overlap nowhere: touching is GEOS's touches
                assert geoms[name].touches(geoms[other])
    return pairs


def test_neighbours_match_touches(coverage):
    f, geoms, keys = coverage
    assert _check_neighbours(f, geoms, keys) > 10
    nb = f.neighbours("diag_a")
    assert [keys[j] for j in nb["feature"]] == ["diag_b"] and nb["touch"][0] == "vertex"
    nb = f.neighbours("enclave")
    assert [keys[j] for j in nb["feature"]] == ["ring"]
    assert nb["length"][0] == pytest.approx(40.0)


def test_neighbours_of_lines(lines):
    f, geoms, keys = lines
    _check_neighbours(f, geoms, keys)
    assert len(f.neighbours("l4")["feature"]) == 0


def test_adjacency_is_the_neighbours(coverage):
    f, geoms, keys = coverage
    queen, rook = f.adjacency(), f.adjacency(queen=False)
    n = len(keys)
    assert queen.shape == (n, n) and (queen != queen.T).nnz == 0
    for k, name in enumerate(keys):
        for j, other in enumerate(keys):
            want = _oracle_touch(geoms[name], geoms[other]) if j != k else None
            assert bool(queen[k, j]) == (want is not None)
            assert bool(rook[k, j]) == (want is not None and want[0] == "edge")
    lengths = f.adjacency(queen=False, weights=True)
    a, b = keys.index("ring"), keys.index("enclave")
    assert lengths[a, b] == pytest.approx(40.0)


def test_weights_with_libpysal(coverage):
    pytest.importorskip("libpysal")
    f, geoms, keys = coverage
    w = f.weights()
    for k, name in enumerate(keys):
        want = {j for j, other in enumerate(keys)
                if j != k and _oracle_touch(geoms[name], geoms[other])}
        assert set(w.neighbors[k]) == want


# ---- nearest -------------------------------------------------------------------------

def test_nearest_matches_distance(coverage, lines):
    for f, geoms, keys in (coverage, lines):
        border = unary_union([_boundary(g) for g in geoms.values()])
        rng = random.Random(11)
        xs = [float(int(rng.uniform(O - 30, O + 130))) for _ in range(300)]
        ys = [float(int(rng.uniform(O - 30, O + 130))) for _ in range(300)]
        r = f.nearest(np.array(xs), np.array(ys))
        for k, (x, y) in enumerate(zip(xs, ys)):
            want = border.distance(Point(x, y))
            assert r["distance"][k] == pytest.approx(want, rel=1e-12, abs=1e-9), (x, y)
            got = Point(r["x"][k], r["y"][k])
            assert got.distance(Point(x, y)) == pytest.approx(want, rel=1e-9, abs=1e-9)
            assert border.distance(got) < 1e-9
            e = f.edge_geometry(int(r["edge"][k]))
            assert e.distance(Point(x, y)) == pytest.approx(want, rel=1e-12, abs=1e-9)


def test_nearest_of_a_feature(coverage):
    f, geoms, keys = coverage
    r = f.nearest([O + 25.0, O + 95.0], [O + 25.0, O + 95.0], feature="ring")
    for k, (x, y) in enumerate([(O + 25, O + 25), (O + 95, O + 95)]):
        want = geoms["ring"].boundary.distance(Point(x, y))
        assert r["distance"][k] == pytest.approx(want)


def test_edges_within(coverage):
    f, geoms, keys = coverage
    edges = [f.edge_geometry(e) for e in range(f.geometry_info["edges"])]
    for x, y, d in [(O + 25, O + 25, 5), (O + 3, O + 7, 12.5), (O + 200, O + 200, 1)]:
        r = f.edges_within(float(x), float(y), d)
        want = [e for e, g in enumerate(edges) if g.distance(Point(x, y)) <= d]
        assert r["edge"].tolist() == want


# ---- dissolve and mesh ---------------------------------------------------------------

def test_dissolve_matches_unary_union(coverage):
    f, geoms, keys = coverage
    frame = f.dissolve("grp", coords="user")
    groups = sorted({g for g in GROUP.values() if g is not None})
    assert list(frame.index) == groups
    for g in groups:
        want = unary_union([geoms[n] for n in keys if GROUP[n] == g])
        got = frame.loc[g, "geometry"]
        assert got.is_valid
        assert got.area == pytest.approx(want.area)
        assert got.symmetric_difference(want).area == pytest.approx(0, abs=1e-9)
        assert got.hausdorff_distance(want) <= 0.5
        assert frame.loc[g, "features"] == sum(GROUP[n] == g for n in keys)
    # the ring and its enclave merge into one polygon without a hole
    both = f.union(["ring", "enclave"])
    assert len(both.geoms) == 1 and len(both.geoms[0].interiors) == 0
    assert len(f.union(["ring"]).geoms[0].interiors) == 1


def test_mesh_lengths(coverage):
    f, geoms, keys = coverage
    outline = unary_union(list(geoms.values())).boundary
    total = sum(g.boundary.length for g in geoms.values())
    assert f.mesh("exterior").length == pytest.approx(outline.length)
    assert f.mesh("interior").length == pytest.approx((total - outline.length) / 2)
    assert f.mesh("all").length == pytest.approx((total + outline.length) / 2)
    between = sum(_boundary(geoms[a]).intersection(_boundary(geoms[b])).length
                  for i, a in enumerate(keys) for b in keys[i + 1:]
                  if GROUP[a] is not None and GROUP[b] is not None and GROUP[a] != GROUP[b])
    assert f.mesh("grp").length == pytest.approx(between)
    assert isinstance(f.mesh(), MultiLineString)


# ---- bad input ------------------------------------------------------------------------

def test_bad_arguments(coverage):
    f, geoms, keys = coverage
    with pytest.raises(KeyError):
        f.neighbours("nowhere")
    with pytest.raises(IndexError):
        f.neighbours(len(keys))
    with pytest.raises(ValueError):
        f.nearest(float("nan"), 0.0)
    with pytest.raises(ValueError):
        f.nearest(1e30, 0.0)
    with pytest.raises(ValueError):
        f.window(5.0, 5.0, 1.0, 1.0)
    with pytest.raises(ValueError):
        f.edges_within(O + 1.0, O + 1.0, -1)
    with pytest.raises(KeyError):
        f.dissolve("nope")
    with pytest.raises(KeyError):
        f.mesh("nope")
    with pytest.raises(ValueError):
        f.dissolve([1, 2])


def test_cli_agrees(coverage, inspect_tool):
    import subprocess

    f, geoms, keys = coverage
    path = f.path if hasattr(f, "path") else None
    if path is None:
        pytest.skip("the file's path is not known")
    out = subprocess.run([inspect_tool, "--neighbours", "ring", "--json", str(path)],
                         capture_output=True, text=True, check=True).stdout
    doc = json.loads(out)
    got = {n["key"]: n["touch"] for n in doc["neighbours"]}
    nb = f.neighbours("ring")
    assert got == {keys[j]: t for j, t in zip(nb["feature"], nb["touch"])}
    r = subprocess.run([inspect_tool, "--neighbours", "nowhere", str(path)],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1


def test_cli_dissolve(coverage, inspect_tool):
    """hpfc-inspect --dissolve FIELD and --dissolve-features LIST against
    unary_union of the listed features (area, polygons, holes)."""
    import subprocess

    f, geoms, keys = coverage
    path = f.path if hasattr(f, "path") else None
    if path is None:
        pytest.skip("the file's path is not known")

    def run(*args):
        out = subprocess.run([inspect_tool, *args, "--json", str(path)], capture_output=True,
                             text=True, check=True).stdout
        return json.loads(out)["groups"]

    def holes(g):
        polys = g.geoms if g.geom_type == "MultiPolygon" else [g]
        return sum(len(p.interiors) for p in polys)

    for grp in run("--dissolve", "grp"):
        want = unary_union([geoms[n] for n in keys if GROUP[n] == grp["value"]])
        assert grp["area"] == pytest.approx(want.area)
        assert grp["holes"] == holes(want)
    fid = {n: f.feature(keys.index(n))["fid"] for n in keys}
    lists = [["ring", "enclave"], ["ring"], ["west", "south", "diag_a", "diag_b", "ring"]]
    for names in lists:
        # keys for the first list, fids for the rest
        items = names if names == lists[0] else [str(fid[n]) for n in names]
        (grp,) = run("--dissolve-features", ",".join(items))
        want = unary_union([geoms[n] for n in names])
        polys = len(want.geoms) if want.geom_type == "MultiPolygon" else 1
        assert grp["features"] == len(names)
        assert grp["area"] == pytest.approx(want.area)
        assert (grp["polygons"], grp["holes"]) == (polys, holes(want))
    r = subprocess.run([inspect_tool, "--dissolve-features", "ring,nowhere", str(path)],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1
