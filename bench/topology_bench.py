#!/usr/bin/python3
"""The topology questions against their peers, same layer, same run.

    /usr/bin/python3 bench/topology_bench.py FILE.hpfc LAYER|- FIELD [POINTS] [RUNS]

FILE.hpfc is LAYER packed by hpfc-pack (--fields all); FIELD an attribute
to dissolve by. LAYER "-": the peers get the file's own features
(File.features_geodataframe, what hpfc-inspect --export writes), so that
the answers must agree exactly; a source layer whose invalid polygons
hpfc-pack noded differs from them where GEOS's make_valid repairs
otherwise. Timed, best of RUNS (default 3), wall and CPU of this
thread, the file opened and its index built before (as a peer's frame is
read before):
  - queen adjacency: File.adjacency() (scipy CSR) against
    libpysal.weights.Queen.from_dataframe and geopandas
    sjoin(predicate="touches") on the layer; the pairs must be the same;
  - nearest edge for POINTS random points (default 100,000) in the
    layer's bounds: File.nearest() against shapely's STRtree over the
    features' boundary segments (shapely 2: query_nearest with distances;
    shapely 1.8: nearest() point by point); the distances must agree;
  - dissolve by FIELD: File.dissolve() (a GeoDataFrame) against
    GeoDataFrame.dissolve(FIELD); same areas, symmetric difference;
  - window of 1 % of the extent (centred): File.window() against a
    FlatGeobuf bbox read of the same layer (GDAL, ogr spatial filter),
    the FlatGeobuf written once beside LAYER.
All coordinates in the file's plane (coords="user"); the peers get the
layer reprojected to that plane once, untimed.
"""
import os
import sys
import time


def best_of(fn, runs):
    best = None
    out = None
    for _ in range(runs):
        t0, c0 = time.perf_counter(), time.thread_time()
        out = fn()
        wall, cpu = time.perf_counter() - t0, time.thread_time() - c0
        if best is None or wall < best[0]:
            best = (wall, cpu)
    return out, best


def line(what, t, ref=None):
    ratio = f"  ({ref[0] / t[0]:.1f}x faster)" if ref else ""
    print(f"  {what:58s} {t[0] * 1e3:10.2f} ms wall {t[1] * 1e3:10.2f} ms CPU{ratio}")


def main():
    path, layer, field = sys.argv[1], sys.argv[2], sys.argv[3]
    npts = int(sys.argv[4]) if len(sys.argv) > 4 else 100_000
    runs = int(sys.argv[5]) if len(sys.argv) > 5 else 3
    import geopandas
    import numpy as np
    import shapely
    import hpfc

    f = hpfc.open(path)
    f._shapes()  # the index, built once
    if layer == "-":
        # the oracle: the features as hpfc-inspect --export writes
        # them (the same noded geometry as the file), in the file's plane;
        # fid = row of the layer once the index is the fid
        frame = f.features_geodataframe(coords="user")
        frame = frame.set_index("fid", drop=False)
        frame.index.name = None
        layer = os.path.splitext(path)[0] + ".features.gpkg"
    else:
        frame = geopandas.read_file(layer)
        crs = f.crs_for("user")
        if frame.crs is not None and crs:
            frame = frame.to_crs(crs)
        frame = frame.reset_index(drop=True)  # row = position in the layer = fid
    # a layer read from TopoJSON may hold a GeometryCollection of polygons,
    # which libpysal refuses: its polygons as one MultiPolygon
    from shapely.geometry import MultiPolygon

    def polygonal(g):
        if g is None or g.geom_type in ("Polygon", "MultiPolygon"):
            return g
        parts = [p for p in getattr(g, "geoms", []) if p.geom_type == "Polygon"]
        return MultiPolygon(parts)

    # and GEOS's predicates refuse invalid polygons (hpfc-pack nodes them):
    # the peers get them made valid, untimed
    from shapely.validation import make_valid

    frame["geometry"] = frame.geometry.apply(
        lambda g: polygonal(g if g is None or g.is_valid else make_valid(g)))
    # hpfc-pack skips empty geometries; a feature's fid is its row in the
    # layer, which the frame's index keeps once the empty rows are dropped
    frame = frame[~frame.geometry.is_empty]
    fids = np.array([ft["fid"] for ft in f.features()])
    n = len(frame)
    import numpy as np  # noqa: F811
    print(f"{path}: {n} features, {f.geometry_info['edges']} edges; shapely {shapely.__version__}")

    # ---- queen adjacency
    print("queen adjacency")
    adj, t_h = best_of(lambda: f.adjacency(), runs)
    line("hpfc File.adjacency()", t_h)
    pairs_h = {(int(fids[a]), int(fids[b])) for a, b in zip(*adj.nonzero()) if a < b}
    try:
        from libpysal.weights import Queen

        w, t_l = best_of(lambda: Queen.from_dataframe(frame, ids=frame.index.tolist(),
                                                              silence_warnings=True), runs)
        line("libpysal Queen.from_dataframe", t_l)
        pairs_l = {(a, b) for a, nb in w.neighbors.items() for b in nb if a < b}
        print(f"    pairs: hpfc {len(pairs_h)}, libpysal {len(pairs_l)}, "
              f"same {len(pairs_h & pairs_l)}; speedup {t_l[0] / t_h[0]:.1f}x")
    except ImportError:
        print("    libpysal not installed")
    j, t_s = best_of(lambda: geopandas.sjoin(frame, frame, predicate="touches"), runs)
    line("geopandas sjoin(predicate='touches')", t_s)
    pairs_s = {(int(a), int(b)) for a, b in zip(j.index, j["index_right"]) if a < b}
    print(f"    pairs: sjoin {len(pairs_s)}, same as hpfc {len(pairs_h & pairs_s)}; "
          f"speedup {t_s[0] / t_h[0]:.1f}x")

    # ---- nearest edge
    print(f"nearest edge, {npts} points")
    # points near the data, as geocoded points are: each uniform in the
    # bounding box of a feature drawn at random (a layer's own box may span
    # the globe: the Aleutians cross the antimeridian)
    rng = np.random.default_rng(7)
    b = frame.bounds.to_numpy()[rng.integers(0, n, npts)]
    xs, ys = rng.uniform(b[:, 0], b[:, 2]), rng.uniform(b[:, 1], b[:, 3])
    x0, y0, x1, y1 = frame.total_bounds
    r, t_h = best_of(lambda: f.nearest(xs, ys), runs)
    line("hpfc File.nearest()", t_h)
    # the peer's index over the same borders: every edge of the map as a line
    edges = f.edge_arrays().to_shapely("user")
    tree_t0 = time.perf_counter()
    try:
        from shapely import STRtree
    except ImportError:
        from shapely.strtree import STRtree
    tree = STRtree(edges)
    t_build = time.perf_counter() - tree_t0
    if hasattr(tree, "query_nearest"):
        import shapely

        pts = shapely.points(xs, ys)
        (idx, d), t_s = best_of(lambda: tree.query_nearest(pts, return_distance=True,
                                                          all_matches=False), 1)
        dist = np.empty(npts)
        dist[idx[0]] = d
        line(f"shapely STRtree.query_nearest (+{t_build * 1e3:.0f} ms build)", t_s)
    else:
        from shapely.geometry import Point

        m = min(npts, 5_000)
        pts = [Point(x, y) for x, y in zip(xs[:m], ys[:m])]
        near, t_s = best_of(lambda: [tree.nearest(p) for p in pts], 1)
        dist = np.array([g.distance(p) for g, p in zip(near, pts)])
        t_s = (t_s[0] * npts / m, t_s[1] * npts / m)
        line(f"shapely 1.8 STRtree.nearest, {m} points scaled (+{t_build * 1e3:.0f} ms build)",
             t_s)
    k = len(dist)
    diff = np.abs(r["distance"][:k] - dist)
    print(f"    distances: max |hpfc - shapely| {diff.max():.3g} over {k} points; "
          f"speedup {t_s[0] / t_h[0]:.1f}x")

    # ---- dissolve
    print(f"dissolve by {field}")
    d_h, t_h = best_of(lambda: f.dissolve(field, coords="user"), runs)
    line("hpfc File.dissolve() (GeoDataFrame)", t_h)
    d_g, t_g = best_of(lambda: frame.dissolve(field), runs)
    line("geopandas GeoDataFrame.dissolve", t_g)
    common = [v for v in d_h.index if v in d_g.index]
    worst_area = max(abs(d_h.loc[v, "geometry"].area - d_g.loc[v, "geometry"].area) /
                     d_g.loc[v, "geometry"].area for v in common)
    sym = sum(d_h.loc[v, "geometry"].symmetric_difference(d_g.loc[v, "geometry"]).area
              for v in common)
    total = sum(d_g.loc[v, "geometry"].area for v in common)
    print(f"    groups {len(d_h)} / {len(d_g)}; worst relative area difference "
          f"{worst_area:.2e}; symmetric difference {sym / total:.2e} of the area; "
          f"speedup {t_g[0] / t_h[0]:.1f}x")

    # ---- window of 1 % of the extent
    print("window, 1 % of the extent")
    # centred on the data's median point (the box's centre may be sea)
    cx, cy = float(np.median(xs)), float(np.median(ys))
    hw, hh = (x1 - x0) * 0.05, (y1 - y0) * 0.05
    wnd, t_h = best_of(lambda: f.window(cx - hw, cy - hh, cx + hw, cy + hh), runs)
    line("hpfc File.window() (features, faces, edges)", t_h)
    fgb = os.path.splitext(layer)[0] + ".bench.fgb"
    if not os.path.exists(fgb):
        frame.to_file(fgb, driver="FlatGeobuf")
    from osgeo import ogr

    def fgb_read():
        ds = ogr.Open(fgb)
        lyr = ds.GetLayer(0)
        lyr.SetSpatialFilterRect(cx - hw, cy - hh, cx + hw, cy + hh)
        return [ft.GetFID() for ft in lyr]

    got, t_f = best_of(fgb_read, runs)
    line("FlatGeobuf bbox read (GDAL, spatial filter)", t_f)
    print(f"    features: hpfc {len(wnd['features'])}, FlatGeobuf {len(got)} (its bbox "
          f"filter is by feature box); speedup {t_f[0] / t_h[0]:.1f}x")


if __name__ == "__main__":
    main()
