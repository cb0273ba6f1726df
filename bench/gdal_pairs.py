"""Issue 30's "no slower than FlatGeobuf" targets as paired whole processes.

Usage: gdal_pairs.py DIR PAIRS (bench/run-gdal.sh runs it after
gdal_bench.py). DIR holds counties.hpfc, counties_srs.fgb, countries.hpfc
and countries_srs.fgb (FlatGeobuf with the EPSG:4326 the .hpfc carries:
making any SRS opens PROJ's database, so the fair pair has one on each
side).

Each pair runs the .hpfc command and the FlatGeobuf one back to back, the
first of the two alternating, and takes the ratio of their CPU times
(user + system of the child). A pair's two runs see the same machine, so
the ratios hold still where the times drift; the median ratio and its
quartiles are printed, with the share of pairs the .hpfc side won.
"""

import os
import resource
import statistics
import subprocess
import sys

DIR, PAIRS = sys.argv[1], int(sys.argv[2])


def path(name):
    return os.path.join(DIR, name)


def cpu(cmd):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def pairs(title, hpfc_cmd, fgb_cmd):
    cpu(hpfc_cmd), cpu(fgb_cmd)  # the files' pages and the libraries in the cache
    ratios, hpfc_times, fgb_times = [], [], []
    for k in range(PAIRS):
        if k % 2:
            f = cpu(fgb_cmd)
            h = cpu(hpfc_cmd)
        else:
            h = cpu(hpfc_cmd)
            f = cpu(fgb_cmd)
        hpfc_times.append(h)
        fgb_times.append(f)
        ratios.append(h / f)
    q1, med, q3 = statistics.quantiles(ratios, n=4)
    won = sum(r < 1 for r in ratios)
    print(f"{title}\n  {PAIRS} pairs: hpfc / FlatGeobuf CPU median {med:.3f}x"
          f" (quartiles {q1:.3f}-{q3:.3f}; .hpfc faster in {won} of {PAIRS});"
          f" medians {statistics.median(hpfc_times) * 1000:.1f} against"
          f" {statistics.median(fgb_times) * 1000:.1f} ms")
    sys.stdout.flush()


SPAT = ["-spat", "-102.1", "37.0", "-99.5", "39.0"]  # gdal_bench.py's window: 35 counties
pairs("ogrinfo -spat, 1 % of us-atlas counties",
      ["ogrinfo", "-ro", "-q", path("counties.hpfc"), "counties"] + SPAT,
      ["ogrinfo", "-ro", "-q", path("counties_srs.fgb"), "counties"] + SPAT)
GP = ("import fiona, geopandas, sys; fiona.supported_drivers['HPFC'] = 'r'; "
      "df = geopandas.read_file(sys.argv[1], layer='countries', engine='fiona'); assert len(df) > 200")
pairs("geopandas.read_file, world-atlas countries-10m (python3 -c, with imports)",
      ["/usr/bin/python3", "-c", GP, path("countries.hpfc")],
      ["/usr/bin/python3", "-c", GP, path("countries_srs.fgb")])
