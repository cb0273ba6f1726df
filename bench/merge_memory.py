"""The merge's own memory (issue 32: "proportional to partition borders, not
to the map"): the parts of a .pfc cut and built in one process, then joined
and written in a fresh one, without GEOM (which would read the whole graph
again), its peak resident memory against the interpreter's own.

The join reads the part files where they lie (hpfc_tree_merge_files maps
them), so the resident peak counts pages of the part files that the page
cache holds and the kernel may drop at any time. A thread samples
/proc/self/status every 2 ms for the two kinds apart: RssAnon (the memory
the merge needs) and RssFile (mapped files), and the peak of each.

    PYTHONPATH=<the hpfc package> python3 bench/merge_memory.py GRAPH.pfc PARTS [GRAPH.pfc ...]
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


def merge(src, parts, directory):
    from hpfc import _hpfc
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    paths = [os.path.join(directory, "part-%d.part" % k) for k in range(parts)]
    out = os.path.join(directory, "out.hpfc")
    sampler = RssSampler()
    sampler.sample()
    base_anon = sampler.anon
    sampler.start()
    t0 = time.perf_counter()
    _hpfc._pack_merge(paths, src, out, 2, True, False)
    wall = time.perf_counter() - t0
    sampler.stop.set()
    sampler.join()
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    size = sum(os.path.getsize(p) for p in paths) / 1e6
    print("%-28s parts %4d  merge %6.2f s  peak %6.0f MB (interpreter %3.0f)  anon %6.0f MB "
          "(interpreter %3.0f)  file-backed %6.0f MB  part files %6.0f MB  file %6.0f MB" %
          (os.path.basename(src), parts, wall, peak, base, sampler.anon, base_anon, sampler.file,
           size, os.path.getsize(out) / 1e6))


def main():
    # each step in a process of its own, started from this small one: a
    # forked child's peak would count its parent's pages
    if len(sys.argv) > 1 and sys.argv[1] == "--cut":
        print(cut_and_build(sys.argv[2], int(sys.argv[3]), sys.argv[4]))
        return
    if len(sys.argv) > 1 and sys.argv[1] == "--merge":
        merge(sys.argv[2], int(sys.argv[3]), sys.argv[4])
        return
    parts = int(sys.argv[2])
    for src in [sys.argv[1]] + sys.argv[3:]:
        with tempfile.TemporaryDirectory() as directory:
            n = subprocess.run([sys.executable, __file__, "--cut", src, str(parts), directory], check=True,
                               capture_output=True, text=True).stdout.split()[-1]
            subprocess.run([sys.executable, __file__, "--merge", src, n, directory], check=True)


if __name__ == "__main__":
    main()
