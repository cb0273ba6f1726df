"""hpfc.pack on a 2-worker LocalCluster (issue 32): wall time, the client's
and each worker's peak resident memory (and hpfc-pack's, which reads, cuts
and joins any input but .pfc), for bench/README.md "A build in parts".

    PYTHONPATH=<the hpfc package> python3 bench/dask_pack_bench.py [--read-here] INPUT PARTS [OUT [HPFC-PACK-OPTION...]]

HPFC_PACK names the hpfc-pack to run (else PATH). --read-here reads a .pfc
in the client, a GIS layer's features in hpfc-pack (read_on_workers=False;
else the workers read them in ranges, one a worker, whose hpfc-pack
--read-range peaks are printed too). The client's peak is also given as
its own (anonymous) memory, sampled every 20 ms from /proc/self/status:
its resident peak counts the pages of the mapped graph file, which are the
page cache's. The workers' own memory likewise (their resident peak counts
the .pfc text and the graph file they map).
"""
import resource
import sys
import threading
import time


def _status_kb(field):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    return 0


class _AnonPeak(threading.Thread):
    """The largest RssAnon of this process, sampled until stopped, overall
    and per stage of hpfc.pack (the stage its progress names last)."""

    def __init__(self):
        super().__init__(daemon=True)
        self.peak, self.done = 0, threading.Event()
        self.stage, self.stages = "start", {}

    def run(self):
        while not self.done.wait(0.02):
            kb = _status_kb("RssAnon")
            self.peak = max(self.peak, kb)
            self.stages[self.stage] = max(self.stages.get(self.stage, 0), kb)

import hpfc
from dask.distributed import Client, LocalCluster


def _start_sampler(dask_worker):
    """On a worker: its own RssAnon peak sampled from now on."""
    sampler = _AnonPeak()
    dask_worker.hpfc_anon = sampler
    sampler.start()
    return _status_kb("RssAnon")


def _stop_sampler(dask_worker):
    sampler = dask_worker.hpfc_anon
    sampler.done.set()
    sampler.join()
    return sampler.peak


def main():
    argv = sys.argv[1:]
    here = "--read-here" in argv[:1]
    argv = argv[1:] if here else argv
    src, n = argv[0], int(argv[1])
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
    c = Client(cluster)
    before = _status_kb("RssAnon")
    worker_before = c.run(_start_sampler)
    sampler = _AnonPeak()
    shown = hpfc._pack._progress

    def progress(stage, done=None, total=None):
        if stage is not None:
            sampler.stage = stage
        shown(stage, done, total)

    hpfc._pack._progress = progress
    sampler.start()
    t0 = time.perf_counter()
    out = argv[2] if len(argv) > 2 else "/tmp/dask_out.hpfc"
    hpfc.pack(src, out, client=c, partitions=n, shared_dir="/tmp", options=argv[3:],
              read_on_workers=not here)
    wall = time.perf_counter() - t0
    sampler.done.set()
    sampler.join()
    worker_own = c.run(_stop_sampler)
    # the only child waited for so far: hpfc-pack, when it ran (not the nannies)
    ran_tool = not src.endswith(".pfc") or len(argv) > 3
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    tool_mb = children.ru_maxrss / 1024 if ran_tool else float("nan")
    tool_cpu = children.ru_utime + children.ru_stime
    peaks = c.run(lambda: resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
    # a worker's children: the hpfc-pack --read-range of a GIS layer's ranges
    readers = c.run(lambda: resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
    readers_cpu = c.run(lambda: resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime +
                        resource.getrusage(resource.RUSAGE_CHILDREN).ru_stime)
    client_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print("wall %.2f s, client peak %.0f MB (own %.0f MB above its %.0f MB before the pack), "
          "hpfc-pack peak %.0f MB, worker peaks %s MB (own %s MB above their start)"
          % (wall, client_mb, (sampler.peak - before) / 1024, before / 1024, tool_mb,
             [round(v / 1024) for v in peaks.values()],
             [round((worker_own[w] - worker_before[w]) / 1024) for w in worker_own]))
    if ran_tool:
        print("hpfc-pack's CPU %.1f s" % tool_cpu)
    if any(readers.values()):
        print("range readers (hpfc-pack --read-range, by worker): peaks %s MB, CPU %s s"
              % ([round(v / 1024) for v in readers.values()],
                 [round(v, 1) for v in readers_cpu.values()]))
    print("client's own peak by stage (MB above its start): " +
          ", ".join("%s %.0f" % (k, (v - before) / 1024) for k, v in sampler.stages.items()))
    c.close()
    cluster.close()


if __name__ == "__main__":
    main()
