"""Times the GDAL driver against FlatGeobuf (bench/run-gdal.sh).

Usage: gdal_bench.py DIR RUNS. DIR holds counties.{hpfc,fgb} and
countries.{hpfc,fgb}. Each case runs RUNS times, the formats interleaved;
prints wall and CPU (user + system of the child) medians and their ratio.
"""

import os
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
    for _ in range(RUNS):
        for label, cmd in cases:
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
