"""The GDAL driver's open and window in one process, against FlatGeobuf.

Usage: gdal_open_bench.py RUNS LAYER X0 Y0 X1 Y1 FILE [FILE ...]
(bench/run-gdal-open.sh). For each file, best of RUNS, with osgeo.ogr:
  open      gdal.OpenEx of the file, its layer named LAYER taken
  window    open, then every feature of the rectangle (SetSpatialFilterRect)
  all       open, then every feature of the layer
An .hpfc file is timed twice: as GDAL opens it by default (the driver
checks every section's CRC-32C) and with VERIFY_CHECKSUMS=NO (the open
then reads no more of the file than the answer needs).
"""

import sys
import time

from osgeo import gdal, ogr

gdal.UseExceptions()
RUNS, LAYER = int(sys.argv[1]), sys.argv[2]
RECT = [float(v) for v in sys.argv[3:7]]
FILES = sys.argv[7:]


def best(fn):
    times = []
    for _ in range(RUNS):
        t0 = time.perf_counter()
        n = fn()
        times.append(time.perf_counter() - t0)
    return min(times) * 1000, n


def opener(path, options):
    def open_layer():
        ds = gdal.OpenEx(path, gdal.OF_VECTOR, open_options=options)
        return ds, ds.GetLayerByName(LAYER)
    return open_layer


def cases(path, options):
    open_layer = opener(path, options)

    def just_open():
        ds, layer = open_layer()
        return 0 if layer is None else 1

    def window():
        ds, layer = open_layer()
        layer.SetSpatialFilterRect(*RECT)
        return sum(1 for _ in layer)

    def every():
        ds, layer = open_layer()
        return sum(1 for _ in layer)
    return [("open", just_open), ("window", window), ("all", every)]


for path in FILES:
    variants = [("", [])]
    if path.endswith(".hpfc"):
        variants.append((" VERIFY_CHECKSUMS=NO", ["VERIFY_CHECKSUMS=NO"]))
    for label, options in variants:
        row = []
        for name, fn in cases(path, options):
            ms, n = best(fn)
            row.append(f"{name} {ms:9.3f} ms ({n})")
        print(f"{path}{label}:\n  " + "   ".join(row), flush=True)
