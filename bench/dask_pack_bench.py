"""hpfc.pack on a 2-worker LocalCluster (issue 32): wall time, the client's
and each worker's peak resident memory (and hpfc-pack's, which reads, cuts
and joins any input but .pfc), for bench/README.md "A build in parts".

    PYTHONPATH=<the hpfc package> python3 bench/dask_pack_bench.py INPUT PARTS [OUT [HPFC-PACK-OPTION...]]

HPFC_PACK names the hpfc-pack to run (else PATH).
"""
import resource
import sys
import time

import hpfc
from dask.distributed import Client, LocalCluster


def main():
    src, n = sys.argv[1], int(sys.argv[2])
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
    c = Client(cluster)
    t0 = time.perf_counter()
    out = sys.argv[3] if len(sys.argv) > 3 else "/tmp/dask_out.hpfc"
    hpfc.pack(src, out, client=c, partitions=n, shared_dir="/tmp", options=sys.argv[4:])
    wall = time.perf_counter() - t0
    # the only child waited for so far: hpfc-pack, when it ran (not the nannies)
    ran_tool = not src.endswith(".pfc") or len(sys.argv) > 4
    tool_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024 if ran_tool else float("nan")
    peaks = c.run(lambda: resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
    client_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print("wall %.2f s, client peak %.0f MB, hpfc-pack peak %.0f MB, worker peaks %s MB"
          % (wall, client_mb, tool_mb, [round(v / 1024) for v in peaks.values()]))
    c.close()
    cluster.close()


if __name__ == "__main__":
    main()
