#!/usr/bin/env python3
"""Pool sizes of both layouts in one run.

usage: python3 bench/pool_sizes.py HPFC_PACK HPFC_INSPECT NAME -- PACK_ARGS... [;; NAME -- ...]

Packs each input twice, --layout paper and --layout compact, with the same
options, and prints per layout: edges, pixels, the file's bytes, the POOL
section's bytes, bits per edge of the whole file and of the pools alone
(the FEAT and CRS sections are the same in both), pool bits per pixel, and
the paper / compact ratio of the pools. Beside them, for reference, the
literature's figures a reader would weigh them against: Draco's edgebreaker
connectivity (about 1-7 bits per edge, no random access) and a half-edge
array (next and twin, 2 x 2 x 32 = 128 bits a half-edge pair per edge's two
darts: 256 bits per edge).
"""
import json
import os
import subprocess
import sys
import tempfile


def pack(tool, inspect, args, layout, out):
    r = subprocess.run([tool, "--json", "--layout", layout] + args + ["-o", out],
                       capture_output=True, text=True, check=True)
    report = json.loads(r.stdout)
    info = json.loads(subprocess.run([inspect, "--json", out], capture_output=True, text=True,
                                     check=True).stdout)
    pool = next(s["length"] for s in info["sections"] if s["tag"] == "POOL")
    return report, pool


def main(argv):
    tool, inspect = argv[0], argv[1]
    cases, cur = [], []
    for a in argv[2:] + [";;"]:
        if a == ";;":
            if cur:
                cases.append((cur[0], cur[2:]))
            cur = []
        else:
            cur.append(a)
    print(f"{'layer':<28} {'layout':<8} {'edges':>8} {'pixels':>9} {'file_B':>9} {'pool_B':>9} "
          f"{'b/edge':>7} {'pool_b/e':>8} {'pool_b/px':>9} {'ratio':>6}")
    with tempfile.TemporaryDirectory() as tmp:
        for name, args in cases:
            got = {}
            for layout in ("paper", "compact"):
                report, pool = pack(tool, inspect, args, layout, os.path.join(tmp, layout + ".hpfc"))
                got[layout] = (report, pool)
            for layout in ("paper", "compact"):
                report, pool = got[layout]
                e, px = report["edges"], report["total_pixels"]
                ratio = got["paper"][1] / pool
                print(f"{name:<28} {layout:<8} {e:>8} {px:>9} {report['file_bytes']:>9} {pool:>9} "
                      f"{8 * report['file_bytes'] / e:>7.2f} {8 * pool / e:>8.2f} {8 * pool / px:>9.2f} "
                      f"{ratio:>6.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
