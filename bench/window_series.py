#!/usr/bin/python3
"""The window query as the file grows: the same window, the same answer,
files from about 1 MB to a few hundred times that (bench/README.md,
"Window as the file grows").

    /usr/bin/python3 bench/window_series.py DIR HPFC_PACK [RUNS]

Four generated continents (bench/gen_continent.py) with cells of one
size and one shape-point density, over nested extents centred on 96 W,
37 N: 40 x 25 cells over a ninth of the conterminous United States' width
and height, 120 x 75 over a third, 360 x 225 over all of it, 720 x 450
over twice it (58.6 M shape points). The window is 1 % of the third
map's extent, centred: it lies in all four maps and holds about the same
cells in each. Written once into DIR: the GeoJSON, the
.hpfc (HPFC_PACK, --key id and --projection none, so that its user
coordinates are the source's degrees and both formats get the same
rectangle) and the FlatGeobuf (ogr2ogr).

Per file, in this process, best of RUNS (default 5), CPU of this thread:
  - hpfc.File.window() (features, faces and edges, each flagged inside or
    crossing), the file opened and its index built before (both printed:
    they grow with the file, the query must not);
  - FlatGeobuf's bbox read through GDAL (spatial filter, FIDs, the fields
    ignored, the geometry read as the filter needs it), the open included,
    as GDAL's index needs none;
  - the HPFC GDAL driver, the same read (open included), where the
    plugin is on GDAL_DRIVER_PATH.
Needs the Python package and osgeo on the path (bench/run-window-series.sh
sets them).
"""
import os
import subprocess
import sys
import time

import hpfc
from osgeo import gdal, ogr

gdal.UseExceptions()
from series_window import CX, CY, E, N, S, W, WINDOW  # noqa: E402  (bench/ is on the path)
SERIES = [("small", 40, 25, 9), ("medium", 120, 75, 3), ("large", 360, 225, 1),
          ("huge", 720, 450, 0.5)]
K = 40  # shape points inside each cell side


def cpu_best(fn, runs):
    best, out = None, None
    for _ in range(runs):
        c0 = time.thread_time()
        out = fn()
        c = time.thread_time() - c0
        best = c if best is None or c < best else best
    return best * 1e3, out


def make(dirname, pack, name, cols, rows, div):
    base = os.path.join(dirname, name)
    hw, hh = (E - W) / div / 2, (N - S) / div / 2
    ext = [CX - hw, CY - hh, CX + hw, CY + hh]
    if not os.path.exists(base + ".geojson"):
        subprocess.run([sys.executable, os.path.join(os.path.dirname(__file__), "gen_continent.py"),
                        base + ".geojson.tmp", str(cols), str(rows), str(K), "1"] +
                       [repr(v) for v in ext], check=True)
        os.replace(base + ".geojson.tmp", base + ".geojson")
    if not os.path.exists(base + ".hpfc"):
        subprocess.run([pack, "-q", "--key", "id", "--projection", "none", base + ".geojson",
                        "-o", base + ".hpfc"], check=True)
    if not os.path.exists(base + ".fgb"):
        # the driver takes a name without .fgb for a folder of layers
        subprocess.run(["ogr2ogr", "-f", "FlatGeobuf", base + ".tmp.fgb", base + ".geojson"],
                       check=True)
        os.replace(base + ".tmp.fgb", base + ".fgb")
    return base


def gdal_fids(path, driver):
    """The FIDs a spatial filter returns, the fields ignored (a spatial
    filter needs the geometry: FlatGeobuf returns nothing without it)."""
    ds = gdal.OpenEx(path, gdal.OF_VECTOR, allowed_drivers=[driver])
    lyr = ds.GetLayer(0)
    defn = lyr.GetLayerDefn()
    lyr.SetIgnoredFields([defn.GetFieldDefn(i).GetName() for i in range(defn.GetFieldCount())])
    lyr.SetSpatialFilterRect(*WINDOW)
    return [ft.GetFID() for ft in lyr]


def main():
    dirname, pack = sys.argv[1], sys.argv[2]
    runs = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    os.makedirs(dirname, exist_ok=True)
    have_driver = gdal.GetDriverByName("HPFC") is not None
    print(f"window {['%.3f' % v for v in WINDOW]} (1 % of the third extent), best of {runs}, "
          "CPU ms")
    print(f"{'file':8s} {'hpfc MB':>8s} {'fgb MB':>7s} {'open+index':>10s} {'window':>8s} "
          f"{'features':>8s} {'faces':>6s} {'edges':>6s} {'fgb bbox':>9s} {'fgb n':>6s} "
          f"{'driver':>8s} {'ratio':>6s}")
    for name, cols, rows, div in SERIES:
        base = make(dirname, pack, name, cols, rows, div)

        def open_index():
            f = hpfc.File(base + ".hpfc")
            f.window(*WINDOW)  # builds the index the queries share
            return f

        t_open, f = cpu_best(open_index, max(1, runs // 2))
        t_win, wnd = cpu_best(lambda: f.window(*WINDOW), runs)
        t_fgb, fids = cpu_best(lambda: gdal_fids(base + ".fgb", "FlatGeobuf"), runs)
        t_drv = cpu_best(lambda: gdal_fids(base + ".hpfc", "HPFC"), runs)[0] if have_driver \
            else float("nan")
        print(f"{name:8s} {os.path.getsize(base + '.hpfc') / 1e6:8.1f} "
              f"{os.path.getsize(base + '.fgb') / 1e6:7.1f} {t_open:10.2f} {t_win:8.2f} "
              f"{len(wnd['features']):8d} {len(wnd['faces']):6d} {len(wnd['edges']):6d} "
              f"{t_fgb:9.2f} {len(fids):6d} {t_drv:8.2f} {t_fgb / t_win:6.2f}")
        f.close()
    print("ratio: FlatGeobuf's bbox read over File.window(); driver: open + filtered read "
          "through the HPFC GDAL driver")


main()
