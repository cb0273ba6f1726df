"""Geometry back from the file: numpy rings,
shapely objects, GeoDataFrames, against oracles that share nothing with the
library: the input .pfc polygonized by shapely (GEOS), the input GeoJSON
read with json + shapely (projected with pyproj when it is lon/lat), and
exact integer arithmetic for the coordinates."""

import json
import math
import random
from fractions import Fraction

import numpy as np
import pytest

import hpfc

from conftest import DATA, TESTS_DATA, VALID_HPFC

try:
    from shapely import geometry as sg
    from shapely.ops import polygonize, unary_union
except ImportError:  # the numpy tests still run
    sg = None
needs_shapely = pytest.mark.skipif(sg is None, reason="shapely is not installed")

GIS_OK = TESTS_DATA / "gis" / "ok"


# ---- oracles ------------------------------------------------------------------------------


def read_pfc(path):
    """The .pfc input as (vertices, edges): edges as lists of lattice points,
    shape points included."""
    verts, edges = [], []
    for line in open(path):
        p = line.split()
        if not p:
            continue
        if p[0] == "v":
            verts.append((int(p[1]), int(p[2])))
        elif p[0] == "e":
            a, b = int(p[1]), int(p[2])
            shape = [(int(p[k]), int(p[k + 1])) for k in range(3, len(p), 2)]
            edges.append([verts[a], *shape, verts[b]])
    return verts, edges


def ring_key(coords):
    """A ring as a canonical tuple: closed point removed, started at its
    smallest point, counter-clockwise."""
    pts = [tuple(int(round(c)) for c in p) for p in coords]
    if pts[0] == pts[-1]:
        pts = pts[:-1]
    area2 = sum(pts[i][0] * pts[(i + 1) % len(pts)][1] - pts[(i + 1) % len(pts)][0] * pts[i][1]
                for i in range(len(pts)))
    if area2 < 0:
        pts.reverse()
    k = pts.index(min(pts))
    return tuple(pts[k:] + pts[:k])


def polygon_key(poly):
    return (ring_key(poly.exterior.coords),
            frozenset(ring_key(r.coords) for r in poly.interiors))


def exact_area2(coords):
    """Twice the signed area of a closed ring of integer points, exactly."""
    pts = [(int(x), int(y)) for x, y in coords]
    return sum(pts[i][0] * pts[i + 1][1] - pts[i + 1][0] * pts[i][1]
               for i in range(len(pts) - 1))


def user_value(v, e):
    """v * 10^e correctly rounded, by Python's exact int arithmetic."""
    return float(v * 10**e) if e >= 0 else v / 10**(-e)


# ---- faces of a .pfc against GEOS's polygonize of its edges ---------------------------------


@pytest.fixture(scope="module", params=["delaunay", "polyline"])
def pfc_case(request, packed):
    source = DATA / ("delaunay-4000.pfc" if request.param == "delaunay" else
                     "polyline-3000.pfc")
    return packed(request.param, source), source


def test_bounds_are_the_box_of_every_input_point(pfc_case, counties):
    path, source = pfc_case
    verts, edges = read_pfc(source)
    pts = verts + [p for e in edges for p in e]
    want = (min(p[0] for p in pts), min(p[1] for p in pts), max(p[0] for p in pts),
            max(p[1] for p in pts))
    with hpfc.open(path) as f:
        assert f.bounds("lattice") == want
        assert f.bounds() == tuple(float(v) for v in f.bounds("user"))
    with hpfc.open(counties[0]) as f:  # user coordinates: the box of every edge's points
        xy = f.edge_arrays().coords("user")
        got = f.bounds()
        assert got == (xy[:, 0].min(), xy[:, 1].min(), xy[:, 0].max(), xy[:, 1].max())
        with pytest.raises(ValueError):
            f.bounds("lonlat")
    with hpfc.open(TESTS_DATA / "valid" / "loop_quadtree.hpfc") as f:  # no GEOM section
        assert f.bounds() is None


@needs_shapely
def test_faces_equal_polygonized_input(pfc_case):
    path, source = pfc_case
    verts, edges = read_pfc(source)
    oracle = {polygon_key(p) for p in polygonize([sg.LineString(e) for e in edges])}
    with hpfc.open(path) as f:
        info = f.geometry_info
        assert info["vertices"] == len(verts) and info["edges"] == len(edges)
        faces = f.face_arrays()
        geoms = faces.to_shapely("lattice")
        got = {polygon_key(g) for g in geoms[1:]}
        assert len(geoms) - 1 == len(oracle)
        assert got == oracle
        # the unbounded face: holes only, enclosing exactly the bounded faces
        assert faces.hole_only[faces.part_offsets[0]:faces.part_offsets[1]].all()
        assert not faces.hole_only[faces.part_offsets[1]:].any()
        bounded = sum(exact_area2(g.exterior.coords) -
                      sum(-exact_area2(r.coords) for r in g.interiors) for g in geoms[1:])
        outer = geoms[0]
        assert sum(exact_area2(p.exterior.coords) for p in outer.geoms) == -bounded or \
            sum(-exact_area2(p.exterior.coords) for p in outer.geoms) == bounded


def test_rings_oriented_closed_simple(pfc_case):
    path, _ = pfc_case
    with hpfc.open(path) as f:
        a = f.face_arrays()
        ro, po = a.ring_offsets, a.polygon_offsets
        for p in range(len(po) - 1):
            for r in range(po[p], po[p + 1]):
                ring = a.xy[ro[r]:ro[r + 1]]
                assert (ring[0] == ring[-1]).all() and len(ring) >= 4
                inner = [tuple(q) for q in ring[:-1]]
                assert len(set(inner)) == len(inner)  # no vertex twice
                area2 = exact_area2(ring)
                outer = r == po[p] and not a.hole_only[p]
                assert (area2 > 0) == outer, (p, r, area2)


@needs_shapely
def test_edges_and_darts_are_the_input_polylines(pfc_case):
    path, source = pfc_case
    verts, edges = read_pfc(source)
    with hpfc.open(path) as f:
        a = f.edge_arrays()
        assert len(a) == len(edges)
        for e, pts in enumerate(edges):
            line = a.xy[a.ring_offsets[e]:a.ring_offsets[e + 1]]
            assert [tuple(p) for p in line] == pts
        for e in range(0, len(edges), 97):
            info = f.edge_info(e)
            assert verts[info["u"]] == edges[e][0] and verts[info["v"]] == edges[e][-1]
            assert info["points"] == len(edges[e])
            assert f.vertex_xy(info["u"]) == edges[e][0]
        darts = list(f.darts())[::13]
        lines = f.dart_arrays(darts)
        for k, d in enumerate(darts):
            e, reversed_ = f.dart_edge(d)
            pts = [tuple(p) for p in lines.xy[lines.ring_offsets[k]:lines.ring_offsets[k + 1]]]
            assert pts == (edges[e][::-1] if reversed_ else edges[e])
            twin = f.dart_geometry(f.twin(d), coords="lattice")
            assert [tuple(map(int, p)) for p in twin.coords] == pts[::-1]
            assert f.dart_geometry(d, "lattice").equals(f.edge_geometry(e, "lattice"))


@needs_shapely
def test_random_points_agree_with_locate(pfc_case):
    path, _ = pfc_case
    with hpfc.open(path) as f:
        i = f.info
        rng = np.random.default_rng(7)
        n = 3000
        xs = rng.integers(i["x0"], i["x0"] + i["width"], n)
        ys = rng.integers(i["y0"], i["y0"] + i["height"], n)
        loc = f.locate_lattice(xs, ys)
        decided = np.nonzero(loc.face > 0)[0]
        assert decided.size >= 20  # every point once location is exact
        faces = sorted(set(loc.face[decided].tolist()))
        shapes = dict(zip(faces, f.face_arrays(faces).to_shapely("lattice")))
        extent = f.face_geometry(0, "lattice")
        # exact location (when the package has it): strictly inside, never
        # on the ring, for points not on a boundary
        strict = getattr(loc, "exact", np.zeros(n, bool)) & \
            ~getattr(loc, "on_boundary", np.zeros(n, bool))
        for k in decided:
            p = sg.Point(int(xs[k]), int(ys[k]))
            face = shapes[int(loc.face[k])]
            assert face.contains(p) if strict[k] else face.covers(p), (k, int(loc.face[k]))
        for k in np.nonzero(loc.face == 0)[0]:
            p = sg.Point(int(xs[k]), int(ys[k]))
            assert not extent.contains(p)


# ---- coordinates: the numpy path against the shapely one, user against exact ---------------


@needs_shapely
def test_numpy_path_equals_shapely_path(packed):
    path = packed("counties", TESTS_DATA / "gis" / "counties_ne.geojson", "--invalid", "node",
                  "--key", "name")
    with hpfc.open(path) as f:
        e = f.unit_exp10
        a = f.feature_arrays()
        user = a.coords("user")
        for (x, y), (u, v) in zip(a.xy[::7], user[::7]):
            assert u == user_value(int(x), e) and v == user_value(int(y), e)
        geoms = a.to_shapely("user")
        ro, po, parts = a.ring_offsets, a.polygon_offsets, a.part_offsets
        for k, g in enumerate(geoms):
            polys = list(g.geoms) if g.geom_type == "MultiPolygon" else [g]
            assert len(polys) == parts[k + 1] - parts[k]
            for p, poly in zip(range(parts[k], parts[k + 1]), polys):
                rings = [poly.exterior, *poly.interiors]
                assert len(rings) == po[p + 1] - po[p]
                for r, ring in zip(range(po[p], po[p + 1]), rings):
                    assert np.array_equal(np.asarray(ring.coords), user[ro[r]:ro[r + 1]])
            single = f.feature_geometry(k)
            assert single.equals(g) and single.wkb == g.wkb
        assert np.array_equal(a.coords("lattice"), a.xy)
        # lon/lat: the inverse projection of the same points
        lonlat = a.coords("lonlat")
        assert np.all(np.abs(lonlat[:, 0]) <= 180) and np.all(np.abs(lonlat[:, 1]) <= 90)
        assert np.array_equal(a.coords("source"), lonlat)


# ---- features against the input GeoJSON -----------------------------------------------------


def input_features(path):
    data = json.load(open(path))
    return [(sg.shape(ft["geometry"]) if ft["geometry"] else None, ft.get("properties") or {})
            for ft in data["features"]]


def check_feature_shapes(f, sources, to_plane, slack):
    """Each feature's geometry (user coordinates) against its source shape
    in the same plane: every source point within half a lattice unit (per
    axis, plus `slack` for the projection) of an output point, every output
    point on the source's boundary within the same, areas equal within
    perimeter x unit. Returns the worst point distance."""
    unit = 10.0**f.unit_exp10
    tol = 0.5 * unit + slack
    geoms = f.features_geometry("user")
    assert len(geoms) == len(sources)
    worst = 0.0
    for k, ((src, _), got) in enumerate(zip(sources, geoms)):
        src = to_plane(src)
        assert got is not None and got.is_valid, k
        assert got.geom_type in ("Polygon", "MultiPolygon")
        out_pts = np.array([c for poly in getattr(got, "geoms", [got])
                            for ring in [poly.exterior, *poly.interiors] for c in ring.coords])
        for poly in getattr(src, "geoms", [src]):
            for ring in [poly.exterior, *poly.interiors]:
                for x, y in ring.coords:
                    d = np.max(np.abs(out_pts - (x, y)), axis=1).min()
                    worst = max(worst, d)
                    assert d <= tol, (k, x, y, d)
        boundary = src.boundary
        for x, y in out_pts[::5]:
            assert boundary.distance(sg.Point(x, y)) <= tol * math.sqrt(2), k
        assert abs(got.area - src.area) <= src.length * unit + 1e-9 * src.area, k
    return worst


@needs_shapely
def test_projected_source_round_trip(packed):
    """A projected (UTM) source: user coordinates are the source's own."""
    src_path = GIS_OK / "projected_utm.geojson"
    path = packed("utm", src_path)
    sources = input_features(src_path)
    with hpfc.open(path) as f:
        assert not f.source_is_lonlat()
        check_feature_shapes(f, sources, lambda g: g, 0.0)
        assert f.crs_for("source") == "EPSG:32618"


@pytest.fixture(scope="module")
def counties(packed):
    src = TESTS_DATA / "gis" / "counties_ne.geojson"
    return packed("counties", src, "--invalid", "node", "--key", "name"), src


@needs_shapely
def test_lonlat_source_round_trip(counties):
    pyproj = pytest.importorskip("pyproj")
    from shapely.ops import transform

    path, src_path = counties
    sources = input_features(src_path)
    valid = [(g, p) for g, p in sources if g.is_valid]
    with hpfc.open(path) as f:
        assert f.source_is_lonlat()
        desc = f.crs.split(";")[0].strip()
        proj = pyproj.Transformer.from_crs("EPSG:4326", desc, always_xy=True)
        # hpfc-pack nodes invalid input (--invalid node): their points may move
        keep = [k for k, (g, _) in enumerate(sources) if g.is_valid]
        geoms = f.features_geometry("user")
        sub = [sources[k] for k in keep]

        class Only:  # the valid features only, in the file's order
            unit_exp10 = f.unit_exp10

            @staticmethod
            def features_geometry(coords):
                return [geoms[k] for k in keep]

        check_feature_shapes(Only, sub, lambda g: transform(proj.transform, g), 1e-6)
        assert len(valid) >= len(sources) - 3
        # lon/lat back: within the projection's error of the source points
        back = f.features_geometry("lonlat")
        for k in keep:
            src = sources[k][0]
            assert back[k].hausdorff_distance(src) < 1e-7 + 2e-8, k


@needs_shapely
def test_random_points_agree_with_input_and_locate(counties):
    path, src_path = counties
    sources = input_features(src_path)
    with hpfc.open(path) as f:
        feats = f.features_geometry("lonlat")
        minx, miny, maxx, maxy = unary_union([g for g, _ in sources]).bounds
        rnd = random.Random(11)
        lon = np.array([rnd.uniform(minx, maxx) for _ in range(2000)])
        lat = np.array([rnd.uniform(miny, maxy) for _ in range(2000)])
        loc = f.locate_lonlat(lon, lat)
        checked = 0
        for k in range(len(lon)):
            p = sg.Point(lon[k], lat[k])
            inside = [j for j, (g, _) in enumerate(sources) if g.contains(p)]
            near = any(g.boundary.distance(p) < 1e-6 for g, _ in sources)
            if near or len(inside) > 1:
                continue  # within a lattice unit of a border, or overlapping input
            mine = [j for j, g in enumerate(feats) if g.contains(p)]
            assert mine == inside, (k, lon[k], lat[k], mine, inside)
            if loc.feature[k] >= 0:
                assert [int(loc.feature[k])] == inside, k
                checked += 1
        assert checked > 50  # every point once location is exact


LINES = {"type": "FeatureCollection",
         "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32618"}},
         "features": [
             {"type": "Feature", "properties": {"name": "a"}, "geometry": {
                 "type": "LineString",
                 "coordinates": [[500000, 4649000], [500400.25, 4649100], [501000, 4649000]]}},
             {"type": "Feature", "properties": {"name": "b"}, "geometry": {
                 "type": "MultiLineString",
                 "coordinates": [[[500000, 4650000], [501000, 4650500]],
                                 [[502000, 4650000], [502500, 4651000], [503000, 4650000]]]}},
             {"type": "Feature", "properties": {"name": "c"}, "geometry": {
                 "type": "LineString",
                 "coordinates": [[504000, 4649000], [505000, 4649000], [505000, 4650000],
                                 [504000, 4649000]]}}]}


@needs_shapely
def test_line_features(packed, tmp_path_factory):
    src_path = tmp_path_factory.mktemp("lines") / "lines.geojson"
    src_path.write_text(json.dumps(LINES))
    path = packed("lines", src_path)
    sources = input_features(src_path)
    with hpfc.open(path) as f:
        assert not f.source_is_lonlat()
        unit = 10.0**f.unit_exp10
        for k, (src, _) in enumerate(sources):
            assert f.feature_face_count(k) == 0
            got = f.feature_geometry(k)
            assert got.geom_type == src.geom_type, k
            # the same lines: every point within half a unit, same lengths
            assert got.hausdorff_distance(src) <= 0.5 * unit * math.sqrt(2), k
            assert abs(got.length - src.length) <= 2 * unit * len(LINES["features"][k]
                                                                  ["geometry"]["coordinates"])
        assert list(f.feature_geometry(2).coords)[0] == list(f.feature_geometry(2).coords)[-1]
        a = f.feature_arrays(lines=True)
        assert a.kind == "lines" and a.polygon_offsets is None and len(a) == 3
        assert list(np.diff(a.part_offsets)) == [1, 2, 1]


@needs_shapely
def test_crossing_line_features(packed):
    """Lines that other lines cross come back whole: hpfc-pack links the
    pieces noding cut to their lines (EDGF)."""
    src_path = GIS_OK / "lines_crossing.geojson"
    path = packed("lines_crossing", src_path)
    sources = input_features(src_path)
    with hpfc.open(path) as f:
        for k, (src, _) in enumerate(sources):
            got = f.feature_geometry(k, "lonlat")
            assert got is not None and got.hausdorff_distance(src) < 1e-7, k


# ---- tables ------------------------------------------------------------------------------


@needs_shapely
def test_geodataframe_of_features_and_faces(counties):
    gpd = pytest.importorskip("geopandas")
    path, src_path = counties
    sources = input_features(src_path)
    with hpfc.open(path) as f:
        gdf = f.features_geodataframe()
        assert isinstance(gdf, gpd.GeoDataFrame)
        assert gdf.crs.to_epsg() == 4326
        assert list(gdf.index) == list(range(len(sources)))
        assert list(gdf["fid"]) == list(range(len(sources)))
        assert list(gdf["name"]) == [p["name"] for _, p in sources]
        assert [c for c, _ in f.attribute_columns] == [c for c in gdf.columns
                                                       if c not in ("fid", "layer", "name",
                                                                    "geometry")]
        for k in range(0, len(sources), 9):
            assert gdf.geometry[k].equals(f.feature_geometry(k, "lonlat"))
        faces = f.faces_geodataframe(coords="user")
        assert faces.crs is not None and not faces.crs.is_geographic
        assert list(faces.index) == list(range(1, f._shapes().face_count))
        for face in faces.index[::11]:
            assert faces.loc[face, "features"] == f.face_features(face)
            assert faces.geometry[face].equals(f.face_geometry(face))
        # the faces tile the features: same total area
        assert abs(faces.geometry.area.sum() - f.features_geodataframe("user").area.sum()) < \
            1e-6 * faces.geometry.area.sum()


@needs_shapely
def test_tables_without_geopandas_or_shapely(counties, monkeypatch):
    pd = pytest.importorskip("pandas")
    import sys

    path, _ = counties
    with hpfc.open(path) as f:
        monkeypatch.setitem(sys.modules, "geopandas", None)
        frame = f.features_geodataframe()
        assert type(frame) is pd.DataFrame and frame.attrs["crs"] == "EPSG:4326"
        assert frame.geometry[0].geom_type in ("Polygon", "MultiPolygon")
        monkeypatch.setitem(sys.modules, "shapely", None)
        records = f.feature_records()
        assert isinstance(records[0]["geometry"], hpfc.RingArrays)
        assert records[0]["geometry"].xy.dtype == np.int64
        faces = f.face_records()
        assert isinstance(faces[0]["geometry"], hpfc.RingArrays)


@needs_shapely
def test_same_as_command_line_export(counties, inspect_tool, tmp_path):
    """features_geodataframe() against hpfc-inspect --export (GeoJSON):
    the same features, fids, keys and geometry, in the same SRS."""
    import subprocess

    path, _ = counties
    out = tmp_path / "export.geojson"
    r = subprocess.run([inspect_tool, str(path), "--export", str(out)], capture_output=True,
                       text=True, check=False)
    if r.returncode != 0 and "GDAL" in r.stderr and "not built" in r.stderr:
        pytest.skip(r.stderr.strip())
    assert r.returncode == 0, r.stderr
    exported = json.loads(out.read_text())
    with hpfc.open(path) as f:
        rows = f.feature_records()
        assert exported["crs"]["properties"]["name"].endswith("CRS84")  # EPSG:4326, lon/lat
        assert f.crs_for("source") == "EPSG:4326"
        assert len(exported["features"]) == len(rows)
        for ft, row in zip(exported["features"], rows):
            assert ft["properties"]["fid"] == row["fid"]
            assert ft["properties"]["name"] == row["name"]
            assert ft["properties"]["source_fid"] == row["source_fid"]
            theirs = sg.shape(ft["geometry"])
            # GDAL's GeoJSON keeps 15 significant digits
            assert theirs.hausdorff_distance(row["geometry"]) < 1e-12, row["fid"]
            assert len(getattr(theirs, "geoms", [theirs])) == \
                len(getattr(row["geometry"], "geoms", [row["geometry"]]))


# ---- bad input ---------------------------------------------------------------------------


def test_files_without_geometry_raise_no_section():
    old = [p for p in VALID_HPFC]
    assert old
    for p in old:
        with hpfc.open(p) as f:
            if f.geometry_info is not None:
                continue
            with pytest.raises(hpfc.Error) as e:
                f.face_arrays([1])
            assert e.value.name == "HPFC_E_NO_SECTION" and e.value.code != 0


@needs_shapely
def test_wrong_arguments(counties):
    path, _ = counties
    f = hpfc.open(path)
    for bad in ("1", 1.5, None, [1]):
        with pytest.raises(TypeError):
            f.face_geometry(bad)
        with pytest.raises(TypeError):
            f.edge_geometry(bad)
    with pytest.raises(TypeError):
        f.face_arrays(["a"])
    with pytest.raises(TypeError):
        f.face_arrays([1.5])
    n = f._shapes().face_count
    for call, limit in ((f.face_geometry, n), (f.feature_geometry, 54),
                        (f.edge_geometry, f.geometry_info["edges"]),
                        (f.vertex_xy, f.geometry_info["vertices"])):
        with pytest.raises(IndexError):
            call(limit)
        with pytest.raises(IndexError):
            call(-1)
        with pytest.raises(IndexError):
            call(2**64)
    with pytest.raises(IndexError):
        f.face_arrays([0, 1, n + 5])
    with pytest.raises(ValueError):
        f.face_geometry(1, coords="degrees")
    with pytest.raises(IndexError):  # not a dart key of this file
        f.dart_geometry(2**63 + 12345)
    a = f.face_arrays([1])
    f.close()
    with pytest.raises(ValueError):
        f.face_geometry(1)
    with pytest.raises(ValueError):
        a.coords("user")
    with pytest.raises(ValueError):
        f.geometry_info


def test_damaged_geometry_raises_never_crashes(counties, tmp_path):
    """GEOM and LABL bytes flipped at random: every geometry call raises
    hpfc.Error (with the library's code) or answers, in a child process
    so that a crash fails the test instead of killing pytest."""
    import subprocess
    import sys

    path, _ = counties
    script = tmp_path / "mutate.py"
    script.write_text(MUTATE)
    r = subprocess.run([sys.executable, str(script), str(path), str(tmp_path), "150"],
                       capture_output=True, text=True, timeout=None, check=False)
    assert r.returncode == 0, r.stderr[-2000:]
    counts = json.loads(r.stdout.splitlines()[-1])
    assert counts["raised"] > 0, counts
    assert set(counts["names"]) <= {"HPFC_E_CORRUPT", "HPFC_E_NOMEM", "HPFC_E_LIMIT",
                                    "HPFC_E_SECTION", "HPFC_E_CHECKSUM", "HPFC_E_TRUNCATED",
                                    "HPFC_E_ARG", "HPFC_E_NO_SECTION"}, counts


MUTATE = r'''
import json, random, sys
import hpfc
try:
    import shapely
except ImportError:
    shapely = None
src, tmp, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
data = bytearray(open(src, "rb").read())
with hpfc.open(src) as f:
    spans = [(s["offset"], s["length"]) for s in f.sections if s["tag"] in ("GEOM", "LABL")]
assert spans, "no GEOM/LABL section"
rnd = random.Random(5)
raised, answered, other, names = 0, 0, 0, set()
for k in range(n):
    d = bytearray(data)
    off, length = rnd.choice(spans)
    for _ in range(rnd.randint(1, 4)):
        pos = off + rnd.randrange(length)
        d[pos] = rnd.randrange(256) if rnd.random() < 0.5 else d[pos] ^ (1 << rnd.randrange(8))
    p = f"{tmp}/m{k % 4}.hpfc"
    open(p, "wb").write(d)
    try:
        with hpfc.open(p, skip_checksum=True) as f:
            faces = f.face_arrays()
            if shapely:
                faces.to_shapely("lattice")
            f.feature_arrays()
            f.edge_arrays()
            f.feature_records("user")
        answered += 1
    except hpfc.Error as e:
        assert isinstance(e.code, int) and e.code != 0 and e.name.startswith("HPFC_E_"), e
        raised += 1
        names.add(e.name)
    except (IndexError, ValueError) as e:  # ids past a corrupt count, unprojectable points
        other += 1
print(json.dumps({"raised": raised, "answered": answered, "other": other,
                  "names": sorted(names)}))
'''


def test_threads_share_a_file(counties):
    """The library's index answers one call at a time; threads take turns
    and each gets the whole answer."""
    from concurrent.futures import ThreadPoolExecutor

    path, _ = counties
    with hpfc.open(path) as f:
        want = f.feature_arrays()
        with ThreadPoolExecutor(4) as pool:
            got = list(pool.map(lambda _: f.feature_arrays(), range(16)))
        for a in got:
            assert np.array_equal(a.xy, want.xy)
            assert np.array_equal(a.ring_offsets, want.ring_offsets)
            assert np.array_equal(a.part_offsets, want.part_offsets)
