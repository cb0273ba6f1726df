#!/usr/bin/python3
"""The Python package against geopandas and against the C batch path.

    /usr/bin/python3 bench/python_bench.py LAYER FILE.hpfc [N] [--layer NAME]
        [--c-bench build/bench/bench_locate_batch] [--open BIG.hpfc]

LAYER is the polygon layer FILE.hpfc was packed from (GDAL-readable: the
TopoJSON of npm's us-atlas, GeoJSON, ...). N random lon/lat points over the
conterminous United States (default 1,000,000, seed 1) are answered three
ways, timed best of --repeats (default 3; geopandas once: it takes minutes):
  - hpfc: File.locate_lonlat (File.locate when the file records no CRS, so
    its coordinates are lon/lat already), after a warm-up call (timed
    apart: numpy's import; files without LABL number their faces there);
  - the C batch path: bench_locate_batch on the same points (same lattice
    conversion, hpfc_locate_batch), whose checksums must equal Python's;
  - geopandas.sjoin(points, polygons, predicate="within") on the same
    points and the layer's polygons (building the points' GeoSeries timed
    apart; sjoin builds its STRtree inside).
It reports how often hpfc's answers name sjoin's polygon: with exact
geometry (format 1.2's default) every point off the borders, else the
points whose leaf meets one face. With --open: `import hpfc; hpfc.open(BIG)` in a fresh
interpreter, and hpfc.open alone against the C open (median of 100).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np


def best_of(fn, repeats, cpu=None):
    """Best wall time of `repeats` calls (and best CPU time of this thread
    into cpu[0], when given), with the last answer."""
    best, out = float("inf"), None
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.thread_time()
        out = fn()
        best = min(best, time.perf_counter() - t0)
        if cpu is not None:
            cpu[0] = min(cpu[0], time.thread_time() - c0)
    return best, out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("layer")
    ap.add_argument("hpfc")
    ap.add_argument("n", nargs="?", type=int, default=1_000_000)
    ap.add_argument("--layer-name", default=None)
    ap.add_argument("--c-bench", default=None)
    ap.add_argument("--open", dest="big", default=None)
    ap.add_argument("--no-geopandas", action="store_true")
    ap.add_argument("--repeats", type=int, default=3, help="best of this many (hpfc, C)")
    args = ap.parse_args()

    import hpfc

    rng = np.random.default_rng(1)
    lon = rng.uniform(-125.0, -66.0, args.n)
    lat = rng.uniform(24.0, 50.0, args.n)
    f = hpfc.open(args.hpfc)
    lonlat = f.crs is not None
    locate = f.locate_lonlat if lonlat else f.locate
    t0 = time.perf_counter()
    locate(lon[:10], lat[:10])
    faces_s = time.perf_counter() - t0
    hp_cpu = [float("inf")]
    hp_s, hits = best_of(lambda: locate(lon, lat), args.repeats, hp_cpu)
    print(f"hpfc        {args.n} points: {hp_s:.3f} s ({hp_s * 1e9 / args.n:.0f} ns/point), "
          f"{hp_cpu[0]:.3f} s CPU; "
          f"first call (numpy's import; older files: the faces numbered): {faces_s:.3f} s; "
          f"{'lon/lat via CRS' if lonlat else 'lon/lat lattice'}")
    print(f"            inside {hits.inside.mean():.3f}, single face {hits.single.mean():.3f}, "
          f"one feature {(hits.feature >= 0).mean():.3f}, some feature {(hits.feature_count > 0).mean():.3f}")

    if args.c_bench:
        with tempfile.NamedTemporaryFile(suffix=".f64", delete=False) as tmp:
            np.concatenate([lon, lat]).astype(np.float64).tofile(tmp)
        try:
            r = subprocess.run([args.c_bench, "locate", args.hpfc, tmp.name,
                                "lonlat" if lonlat else "xy", str(args.repeats)],
                               capture_output=True, text=True, check=True)
        finally:
            os.unlink(tmp.name)
        c = json.loads(r.stdout)
        same = (c["sum_face"] == int((hits.face + 1).sum())
                and c["sum_feature"] == int((hits.feature + 1).sum())
                and c["single"] == int(hits.single.sum()))
        print(f"C batch     {args.n} points: {c['locate_best_s']:.3f} s "
              f"({c['ns_per_point']:.0f} ns/point); Python / C = {hp_s / c['locate_best_s']:.2f} "
              f"wall, {hp_cpu[0] / c['locate_best_cpu_s']:.2f} CPU ({hp_cpu[0]:.3f} s / "
              f"{c['locate_best_cpu_s']:.3f} s); same answers: {same}")

    if not args.no_geopandas:
        join_with_geopandas(args, f, lon, lat, hits, hp_s, hp_cpu[0])
    f.close()
    if args.big:
        open_cost(args)


def join_with_geopandas(args, f, lon, lat, hits, hp_s, hp_cpu):
    import geopandas as gpd

    kw = {"layer": args.layer_name} if args.layer_name else {}
    polys = gpd.read_file(args.layer, **kw)
    t0 = time.perf_counter()
    pts = gpd.GeoDataFrame(geometry=gpd.points_from_xy(lon, lat), crs=polys.crs)
    pts_s = time.perf_counter() - t0
    gp_cpu = [float("inf")]
    gp_s, joined = best_of(lambda: gpd.sjoin(pts, polys, how="left", predicate="within"), 1,
                           gp_cpu)
    print(f"geopandas   sjoin {args.n} points x {len(polys)} polygons: {gp_s:.3f} s wall, "
          f"{gp_cpu[0]:.3f} s CPU (+ {pts_s:.3f} s to build the points); hpfc is "
          f"{gp_s / hp_s:.1f}x faster (wall), {gp_cpu[0] / hp_cpu:.1f}x (CPU)")
    # the same polygon: by the key field the file was packed with (--key)
    key_field = f.features_info["key_field"] if f.has_features else None
    one = hits.feature >= 0
    first = joined[~joined.index.duplicated(keep="first")].reindex(range(args.n))
    inside_sj = first["index_right"].notna().to_numpy()
    if key_field and key_field in first.columns:
        sj_key = first[key_field].to_numpy()
        if hits.exact.all():
            # Exact geometry: every point has one answer (its feature's key,
            # or none); sjoin's "within" names no polygon for a point on a
            # border, so those are counted apart.
            off = ~hits.on_boundary
            hp_key = np.where(one, hits.key, None)
            sj_none = ~inside_sj
            same = np.where(one, sj_key == hits.key, sj_none & (hits.feature_count == 0))
            differ = off & ~same
            print(f"            same answer as sjoin (its polygon's {key_field}, or none for both): "
                  f"{same[off].sum()} of {off.sum()} points off the borders "
                  f"({same[off].mean():.6f}); on a border: {hits.on_boundary.sum()}; "
                  f"hpfc names a feature for {one.mean():.3f}, sjoin for {inside_sj.mean():.3f}")
            for k in np.flatnonzero(differ)[:5]:
                print(f"            differs: lon {lon[k]!r} lat {lat[k]!r}: hpfc {hp_key[k]!r} "
                      f"(features {hits.feature_count[k]}), sjoin {sj_key[k]!r}")
            return
        sure = one & hits.single  # the leaf meets one face: the point's
        agree = (sj_key[sure] == hits.key[sure]).mean() if sure.any() else float("nan")
        cand = one & ~hits.single  # candidates of a stabbed leaf with one feature
        agree_c = (sj_key[cand] == hits.key[cand]).mean() if cand.any() else float("nan")
        print(f"            hpfc's one-face answers naming sjoin's polygon ({key_field}): "
              f"{agree:.4f} of {sure.sum()}; stabbed leaves with one candidate feature: "
              f"{agree_c:.4f} of {cand.sum()}; sjoin finds a polygon for {inside_sj.mean():.3f}")

def open_cost(args):
    import hpfc

    if True:
        code = ("import time; t=time.perf_counter(); import hpfc; f=hpfc.open(%r); "
                "print(time.perf_counter()-t)" % args.big)
        cold = sorted(float(subprocess.run([sys.executable, "-c", code], capture_output=True,
                                           text=True, check=True).stdout) for _ in range(9))
        ts = []
        for _ in range(100):
            t0 = time.perf_counter()
            g = hpfc.open(args.big)
            ts.append(time.perf_counter() - t0)
            g.close()
        ts.sort()
        size = os.path.getsize(args.big) / 2**20
        line = (f"open        {size:.0f} MiB file: import hpfc + hpfc.open in a fresh interpreter "
                f"{cold[4] * 1e3:.1f} ms (median of 9); hpfc.open {ts[50] * 1e6:.1f} us "
                f"(median of 100, best {ts[0] * 1e6:.1f})")
        if args.c_bench:
            r = subprocess.run([args.c_bench, "open", args.big, "100"], capture_output=True,
                               text=True, check=True)
            c = json.loads(r.stdout)
            line += (f"; C hpfc_open {c['open_median_s'] * 1e6:.1f} us "
                     f"(best {c['open_best_s'] * 1e6:.1f})")
        print(line)


if __name__ == "__main__":
    main()
