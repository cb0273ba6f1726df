"""Times the GDAL driver against FlatGeobuf (bench/run-gdal.sh).

Usage: gdal_bench.py DIR RUNS. DIR holds counties.{hpfc,fgb} and
countries.{hpfc,fgb}. Each case runs RUNS times, the formats interleaved
(in a new order each run);
prints wall and CPU (user + system of the child) medians and their ratio.
"""

import os
import random
import resource
import statistics
import subprocess
import sys
import time

DIR, RUNS = sys.argv[1], int(sys.argv[2])


def path(name):
    return os.path.join(DIR, name)


def timed(cmd):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def compare(title, cases):
    """cases: [(label, argv or callable)], run interleaved RUNS times."""
    times = {label: [] for label, _ in cases}
    for r in range(RUNS):
        # a new order each run (seeded: the same on every machine): a case
        # run after a full read is some 10 % slower whatever its format
        # (caches and clocks the heavy process left), so no case may
        # always come after the same one
        order = list(cases)
        random.Random(r).shuffle(order)
        for label, cmd in order:
            times[label].append(timed(cmd))
    print(title)
    base = None
    for label, _ in cases:
        wall = statistics.median(t[0] for t in times[label])
        cpu = statistics.median(t[1] for t in times[label])
        base = base or (wall, cpu)
        print(f"  {label:44s} wall {wall * 1000:8.1f} ms  cpu {cpu * 1000:8.1f} ms"
              f"  ({wall / base[0]:.2f}x / {cpu / base[1]:.2f}x the first)")


# the window: about 1 % of the counties (Kansas and around: 32 of 3,230)
SPAT = ["-102.1", "37.0", "-99.5", "39.0"]


def count(fmt, layer, spat=None):
    out = subprocess.run(["ogrinfo", "-ro", "-q", path("counties." + fmt), layer] +
                         (["-spat"] + spat if spat else []),
                         check=True, capture_output=True, text=True).stdout
    return out.count("OGRFeature(")


print(f"window {SPAT}: {count('hpfc', 'counties', SPAT)} of {count('hpfc', 'counties')} counties"
      f" (FlatGeobuf: {count('fgb', 'counties', SPAT)})")

out = path("out.gpkg")


def to_gpkg(src, layer):
    def run():
        if os.path.exists(out):
            os.remove(out)
        return ["ogr2ogr", "-f", "GPKG", out, src, layer]
    return run


def ogr2ogr_case(src, layer):
    return ["sh", "-c", f"rm -f {out} && ogr2ogr -f GPKG {out} {src} {layer}"]


compare("ogr2ogr -f GPKG, us-atlas counties-10m (3,230 multipolygons)",
        [("from counties.hpfc (HPFC driver)", ogr2ogr_case(path("counties.hpfc"), "counties")),
         ("from counties.fgb (FlatGeobuf)", ogr2ogr_case(path("counties.fgb"), "counties"))])
compare("ogrinfo -spat (1 % of the counties) against a full read",
        [("ogrinfo -spat counties.hpfc", ["ogrinfo", "-ro", "-q", path("counties.hpfc"), "counties", "-spat"] + SPAT),
         ("ogrinfo counties.hpfc (full read)", ["ogrinfo", "-ro", "-q", path("counties.hpfc"), "counties"]),
         ("ogrinfo -spat counties.fgb (indexed bbox)", ["ogrinfo", "-ro", "-q", path("counties.fgb"), "counties", "-spat"] + SPAT),
         ("ogrinfo -spat counties_srs.fgb (EPSG:4326)", ["ogrinfo", "-ro", "-q", path("counties_srs.fgb"), "counties", "-spat"] + SPAT),
         ("ogrinfo counties.fgb (full read)", ["ogrinfo", "-ro", "-q", path("counties.fgb"), "counties"])])
gp = ("import fiona, geopandas, sys; fiona.supported_drivers['HPFC'] = 'r'; "
      "df = geopandas.read_file(sys.argv[1], layer='countries', engine='fiona'); assert len(df) > 200")
compare("geopandas.read_file, world-atlas countries-10m (254 multipolygons), python3 -c with imports",
        [("from countries.hpfc", ["/usr/bin/python3", "-c", gp, path("countries.hpfc")]),
         ("from countries.fgb", ["/usr/bin/python3", "-c", gp, path("countries.fgb")]),
         ("from countries_srs.fgb (EPSG:4326)", ["/usr/bin/python3", "-c", gp, path("countries_srs.fgb")]),
         ("python3 -c 'import fiona, geopandas' alone", ["/usr/bin/python3", "-c", "import fiona, geopandas"])])

# The same reads inside one interpreter, imports and GDAL's start paid once:
# what a notebook or a server that reads many files sees, and the read's
# own ratio, which the process figures above dilute with the imports.
IN_PROCESS = r"""
import statistics, sys, time
import fiona, geopandas
from osgeo import ogr
fiona.supported_drivers['HPFC'] = 'r'
runs, files = int(sys.argv[1]), sys.argv[2:]

def ogr_read(p):
    ds = ogr.Open(p)
    for f in ds.GetLayer(0):
        f.GetGeometryRef()

def gpd_read(p):
    assert len(geopandas.read_file(p, engine='fiona')) > 200

for name, fn in (('OGR full read (osgeo.ogr)', ogr_read), ('geopandas.read_file', gpd_read)):
    times = {p: [] for p in files}
    for p in files:
        fn(p)  # warm: the file's pages and the driver's first use
    for _ in range(runs):
        for p in files:
            t0 = time.perf_counter()
            fn(p)
            times[p].append(time.perf_counter() - t0)
    base = statistics.median(times[files[0]])
    print(name)
    for p in files:
        m = statistics.median(times[p])
        print(f"  {p.split('/')[-1]:44s} {m * 1000:8.1f} ms  ({m / base:.2f}x the first)")
"""
print("world-atlas countries-10m in one process, medians of", 3 * RUNS, "interleaved reads")
sys.stdout.flush()
subprocess.run(["/usr/bin/python3", "-c", IN_PROCESS, str(3 * RUNS), path("countries.hpfc"),
                path("countries_srs.fgb")], check=True)
