#!/usr/bin/env python3
"""Runs hpfc-pack on GIS inputs, one process each, and prints one row per
input: the stages of the pack (from its --json report), the wall time, shape
points per second, and the peak resident memory against the input's size.

    gis_bench.py HPFC_PACK OUTDIR [--OPTION=VALUE...] INPUT...

Options before the inputs go to hpfc-pack (e.g. --vertices=junctions).

Peak RSS is the child's ru_maxrss (getrusage), so each input runs in a
process of its own. The input's size is the file's (a directory's files
summed).
"""
import json
import os
import resource
import subprocess
import sys
import time


def size_of(path):
    if os.path.isdir(path):
        return sum(os.path.getsize(os.path.join(path, f)) for f in os.listdir(path))
    return os.path.getsize(path)


def run(pack, outdir, opts, path):
    out = os.path.join(outdir, os.path.basename(path) + ".hpfc")
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    t0 = time.monotonic()
    proc = subprocess.run([pack, "--json", "--force", *opts, path, "-o", out], capture_output=True,
                          text=True)
    wall = time.monotonic() - t0
    rss_kib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    if proc.returncode != 0:
        sys.exit(f"{path}: {proc.stderr.strip()}")
    if rss_kib <= before:
        print(f"note: {path}: peak RSS not above an earlier run's; run one input per call",
              file=sys.stderr)
    return json.loads(proc.stdout), wall, rss_kib * 1024


def main():
    pack, outdir = sys.argv[1], sys.argv[2]
    opts = [a for a in sys.argv[3:] if a.startswith("--")]
    inputs = [a for a in sys.argv[3:] if not a.startswith("--")]
    head = ("input", "format", "vertices", "MB", "Mpoints", "edges", "read", "project", "node",
            "graph", "build", "write", "total_s", "Mpts/s", "rss_MiB", "rss/in", "noding")
    print(("%-18s %-8s %-9s %6s %7s %8s" + " %7s" * 7 + " %7s %8s %6s  %s") % head)
    for path in inputs:
        r, wall, rss = run(pack, outdir, opts, path)
        g = r["gis_seconds"]
        mb = size_of(path) / 1e6
        pts = r["points_read"]
        print(("%-18s %-8s %-9s %6.1f %7.2f %8d" + " %7.2f" * 7 + " %7.2f %8.0f %6.1f  %s") % (
            os.path.basename(path)[:18], r["input_format"][:8], r["vertex_model"], mb, pts / 1e6,
            r["edges"],
            g["read"], g["project"], g["node"], g["graph"], r["build_seconds"],
            r["write_seconds"], wall, pts / wall / 1e6, rss / 2**20, rss / (mb * 1e6),
            r["noding"]))


main()
