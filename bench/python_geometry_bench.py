#!/usr/bin/python3
"""Geometry from Python: a GeoDataFrame of a packed layer's
features against reading the layer with geopandas, in the same run.

    /usr/bin/python3 bench/python_geometry_bench.py FILE.hpfc LAYER.geojson [RUNS]

Timed, best of RUNS (default 3), interleaved, wall and CPU of this thread:
  - hpfc numpy: File.feature_arrays() (the library's exact rings of every
    feature, lattice int64) plus .coords("lonlat") (inverse projection);
  - hpfc shapely: File.features_geometry("lonlat");
  - hpfc GeoDataFrame: File.features_geodataframe() (geometry in the source
    SRS, fid, key, attributes), open included;
  - geopandas.read_file(LAYER.geojson): the peer a user would run to get
    the same table from the layer the file was packed from.
Prints one line per way and the sizes (features, rings, points).
"""
import sys
import time


def best_of(fn, runs, results):
    for _ in range(runs):
        t0, c0 = time.perf_counter(), time.thread_time()
        out = fn()
        wall, cpu = time.perf_counter() - t0, time.thread_time() - c0
        results.append((wall, cpu))
    return out


def main():
    path, layer = sys.argv[1], sys.argv[2]
    runs = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    import geopandas
    import hpfc

    ways = {
        "hpfc numpy (feature_arrays + coords lonlat)":
            lambda: (lambda f: (f.feature_arrays().coords("lonlat"), f.close()))(hpfc.open(path)),
        "hpfc shapely (features_geometry lonlat)":
            lambda: (lambda f: (f.features_geometry("lonlat"), f.close()))(hpfc.open(path)),
        "hpfc features_geodataframe()":
            lambda: (lambda f: (f.features_geodataframe(), f.close())[0])(hpfc.open(path)),
        "geopandas.read_file(GeoJSON)": lambda: geopandas.read_file(layer),
    }
    times = {name: [] for name in ways}
    outs = {}
    for _ in range(runs):
        for name, fn in ways.items():
            outs[name] = best_of(fn, 1, times[name])
    with hpfc.open(path) as f:
        a = f.feature_arrays()
        print(f"{path}: {len(a)} features, {len(a.ring_offsets) - 1} rings, {len(a.xy)} points; "
              f"GeoJSON {len(outs['geopandas.read_file(GeoJSON)'])} features")
    for name in ways:
        walls = sorted(w for w, _ in times[name])
        cpus = sorted(c for _, c in times[name])
        print(f"{name:48s} wall best {walls[0]:.3f} s (median {walls[len(walls) // 2]:.3f}), "
              f"CPU best {cpus[0]:.3f} s")
    gdf = outs["hpfc features_geodataframe()"]
    print(f"GeoDataFrame: {len(gdf)} rows, columns {list(gdf.columns)}, crs {gdf.crs}")


if __name__ == "__main__":
    main()
