"""Times hpfc-inspect --export against ogr2ogr on one layer, same run.

usage: export_bench.py HPFC_INSPECT PACKED.hpfc LAYER.geojson DIR RUNS

Each run writes a fresh GeoPackage with each tool (interleaved, so drift of
a shared machine hits both alike): hpfc-inspect --export OUT.gpkg PACKED and
ogr2ogr -f GPKG OUT.gpkg LAYER. Prints, per tool, the median and range of
wall and CPU (user + system) seconds, the output's size, and the
ratio of the medians.
"""
import os
import resource
import statistics
import subprocess
import sys
import time


def timed(cmd):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode:
        sys.exit("%s failed: %s" % (cmd[0], p.stderr.decode()[:400]))
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, after.ru_maxrss


def main():
    inspect, packed, layer, out_dir, runs = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5])
    out_h = os.path.join(out_dir, "bench-hpfc.gpkg")
    out_o = os.path.join(out_dir, "bench-ogr2ogr.gpkg")
    res = {"hpfc-inspect --export": [], "ogr2ogr GeoJSON -> GPKG": []}
    for _ in range(runs):
        for path in (out_h, out_o):
            if os.path.exists(path):
                os.remove(path)
        res["hpfc-inspect --export"].append(timed([inspect, "--export", out_h, packed]))
        res["ogr2ogr GeoJSON -> GPKG"].append(timed(["ogr2ogr", "-f", "GPKG", out_o, layer]))
    sizes = {"hpfc-inspect --export": os.path.getsize(out_h), "ogr2ogr GeoJSON -> GPKG": os.path.getsize(out_o)}
    print("input: %s (%d bytes), %s (%d bytes); %d runs each, interleaved" % (
        packed, os.path.getsize(packed), layer, os.path.getsize(layer), runs))
    med = {}
    for tool, rows in res.items():
        wall = [r[0] for r in rows]
        cpu = [r[1] for r in rows]
        med[tool] = (statistics.median(wall), statistics.median(cpu))
        print("%-26s wall %.3f s (%.3f-%.3f)  cpu %.3f s (%.3f-%.3f)  output %d bytes" % (
            tool, med[tool][0], min(wall), max(wall), med[tool][1], min(cpu), max(cpu), sizes[tool]))
    h, o = med["hpfc-inspect --export"], med["ogr2ogr GeoJSON -> GPKG"]
    print("ratio hpfc/ogr2ogr: wall %.2fx, cpu %.2fx" % (h[0] / o[0], h[1] / o[1]))


main()
