"""The merge's own memory (issue 32: "proportional to partition borders, not
to the map"): the parts of a .pfc cut and built in one process, then joined
and written in a fresh one, its peak resident memory against the
interpreter's own. Without GEOM, which would read the whole text again;
with --graph-file, as the Dask client does: the text read a chunk at a
time into a graph file, the parts built from it, and the merge writing
GEOM from the graph file, mapped.

The join reads the part files where they lie (hpfc_tree_merge_files maps
them), so the resident peak counts pages of the part files that the page
cache holds and the kernel may drop at any time. A thread samples
/proc/self/status every 2 ms for the two kinds apart: RssAnon (the memory
the merge needs) and RssFile (mapped files), and the peak of each.

    PYTHONPATH=<the hpfc package> python3 bench/merge_memory.py [--graph-file] GRAPH.pfc PARTS [GRAPH.pfc ...]
"""
import os
import resource
import subprocess
import sys
import tempfile
import threading
import time


class RssSampler(threading.Thread):
    """Peaks of RssAnon and RssFile (MB) while it runs."""

    def __init__(self):
        super().__init__(daemon=True)
        self.anon = self.file = 0.0
        self.stop = threading.Event()

    def sample(self):
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("RssAnon:"):
                    self.anon = max(self.anon, int(line.split()[1]) / 1024)
                elif line.startswith("RssFile:"):
                    self.file = max(self.file, int(line.split()[1]) / 1024)

    def run(self):
        while not self.stop.is_set():
            self.sample()
            time.sleep(0.002)


def cut_and_build(src, parts, directory):
    from hpfc import _hpfc
    plan = _hpfc._pack_cut(src, directory, 64, 64, 2, 2, 16, parts)
    for k in range(plan["parts"]):
        _hpfc._pack_part(directory, plan, k)
    return plan["parts"]


class _InProcess:
    """hpfc._pack's calls on a Dask client, run here one after another."""

    def scheduler_info(self):
        return {"workers": {"here": None}}

    def submit(self, call, *args, pure=True):
        return call(*args)

    def gather(self, results):
        return results


def read_and_build(src, parts, directory):
    """The Dask path's steps in this process: the text into DIR/graph, the
    plan, the edges routed, the parts built from the graph file."""
    from hpfc import _hpfc, _pack
    c = _InProcess()
    ranges, box = _pack._read_pfc(c, src, directory, None)
    plan = _hpfc._pack_plan(os.path.join(directory, "graph"), 64, 64, 2, 2, 16, parts, box)
    for k, (e0, e1) in enumerate(ranges):
        _hpfc._pfc_route(directory, plan, k, e0, e1)
    for k in range(plan["parts"]):
        _hpfc._pack_part_routed(directory, plan, k, len(ranges))
    return plan["parts"]


def merge(src, parts, directory, graph_file):
    from hpfc import _hpfc
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    paths = [os.path.join(directory, "part-%d.part" % k) for k in range(parts)]
    out = os.path.join(directory, "out.hpfc")
    sampler = RssSampler()
    sampler.sample()
    base_anon = sampler.anon
    sampler.start()
    t0 = time.perf_counter()
    if graph_file:
        _hpfc._pack_merge(paths, os.path.join(directory, "graph"), out, 2, True, True, True)
    else:
        _hpfc._pack_merge(paths, src, out, 2, True, False)
    wall = time.perf_counter() - t0
    sampler.stop.set()
    sampler.join()
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    size = sum(os.path.getsize(p) for p in paths) / 1e6
    print("%-28s %s parts %4d  merge %6.2f s  peak %6.0f MB (interpreter %3.0f)  anon %6.0f MB "
          "(interpreter %3.0f)  file-backed %6.0f MB  part files %6.0f MB  file %6.0f MB" %
          (os.path.basename(src), "GEOM" if graph_file else "    ", parts, wall, peak, base, sampler.anon,
           base_anon, sampler.file, size, os.path.getsize(out) / 1e6))


def main():
    # each step in a process of its own, started from this small one: a
    # forked child's peak would count its parent's pages
    argv = sys.argv[1:]
    graph_file = argv[:1] == ["--graph-file"]
    argv = argv[1:] if graph_file else argv
    if argv[0] == "--cut":
        build = read_and_build if graph_file else cut_and_build
        print(build(argv[1], int(argv[2]), argv[3]))
        return
    if argv[0] == "--merge":
        merge(argv[1], int(argv[2]), argv[3], graph_file)
        return
    parts = int(argv[1])
    mode = ["--graph-file"] if graph_file else []
    for src in [argv[0]] + argv[2:]:
        with tempfile.TemporaryDirectory() as directory:
            n = subprocess.run([sys.executable, __file__] + mode + ["--cut", src, str(parts), directory],
                               check=True, capture_output=True, text=True).stdout.split()[-1]
            subprocess.run([sys.executable, __file__] + mode + ["--merge", src, n, directory], check=True)


if __name__ == "__main__":
    main()
