"""Writers that fail cleanly: every program that writes a file (hpfc-pack's
.hpfc, hpfc-inspect's --export-graph, --render SVG and PNG with its world
file, --export through GDAL, and the GDAL driver's create path, ogr2ogr -f
HPFC) meets a file size limit (the disk full as the process sees it:
RLIMIT_FSIZE, as prlimit --fsize sets it), a SIGKILL at a random instant
of its run, and a read-only output directory. After each: OUT is byte for
byte the old file or the new one (the oracle: the same command run
undisturbed in another directory), and the directory holds nothing else,
apart from a killed run's hidden temporary, which must be whole, never a
partial output, and gone after the next run. The old OUT of ogr2ogr is a
real .hpfc file of another map: GDAL deletes an existing dataset it
recognises before it creates one of that name, which an old file of any
other bytes would not reveal.

ogr2ogr runs with the build's plugin from HPFC_GDAL_DRIVER_PATH (and, in a
sanitized build, the sanitizer runtimes from HPFC_GDAL_PRELOAD, as meson
sets both); without them, or without ogr2ogr, it is not tested.

Usage: faults.py PACK INSPECT TESTS_DIR [KILLS]
"""
import os
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time

PACK, INSPECT, TESTS = sys.argv[1:4]
KILLS = int(sys.argv[4]) if len(sys.argv) > 4 else 12
ROOT = os.path.dirname(os.path.abspath(TESTS))
failures = []
rng = random.Random(int(os.environ.get("HPFC_FAULTS_SEED", "33")))
OLD = b"the old output, which a failed run must leave as it is\n"


def fail(msg):
    print("FAIL:", msg)
    failures.append(msg)


def run(cmd, cwd, limit=None, user=None, env=None):
    def pre():
        if limit is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    if user is not None:
        cmd = ["setpriv", "--reuid=%d" % user, "--regid=%d" % user, "--clear-groups"] + cmd
    return subprocess.run(cmd, cwd=cwd, stdin=subprocess.DEVNULL, capture_output=True,
                          preexec_fn=pre, env=env)


def listing(d):
    return sorted(os.listdir(d))


def read(path):
    with open(path, "rb") as f:
        return f.read()


TEMP = re.compile(r"^\.(.+)\.(\d+)\.[0-9a-f]{12}\.tmp$")


# The one stderr line of a failed run: the tools' own, or GDAL's for ogr2ogr.
TOOL_LINE = r"^hpfc-(pack|inspect): "
GDAL_LINE = r"^ERROR \d+: HPFC: "


class Writer:
    """One command writing `outs` (names in its working directory) from
    `inputs` (copied there), over `old` (bytes) where an old OUT is, in
    `env` (None: this one's); a failed run says why in one line matching
    `line`."""

    def __init__(self, name, argv, outs, inputs, old=OLD, env=None, line=TOOL_LINE):
        self.name, self.argv, self.outs, self.inputs = name, argv, outs, inputs
        self.old, self.env, self.line = old, env, line

    def setup(self, d, old):
        os.makedirs(d, exist_ok=True)
        os.chmod(d, 0o755)
        for src in self.inputs:
            shutil.copy(src, d)
        for o in self.outs:
            p = os.path.join(d, o)
            if old:
                with open(p, "wb") as f:
                    f.write(self.old)
            elif os.path.exists(p):
                os.unlink(p)


def expected_files(w, with_outs):
    return sorted([os.path.basename(i) for i in w.inputs] + (list(w.outs) if with_outs else []))


def check_outs(w, d, new, label, old_present=True):
    """Each OUT old or new, never anything else."""
    for o in w.outs:
        p = os.path.join(d, o)
        if not os.path.exists(p):
            if old_present:
                fail(f"{w.name} {label}: {o} is gone")
            continue
        b = read(p)
        if b != w.old and b != new[o]:
            fail(f"{w.name} {label}: {o} is neither the old nor the new output "
                 f"({len(b)} bytes; new {len(new[o])})")


def leftovers(w, d):
    return [n for n in listing(d) if n not in expected_files(w, True)]


def one_line(w, r, label, needle):
    err = r.stderr.decode(errors="replace")
    lines = err.strip("\n").split("\n")
    if r.returncode != 1:
        fail(f"{w.name} {label}: exit status {r.returncode}, expected 1 ({err[:200]!r})")
    elif len(lines) != 1 or not re.match(w.line, lines[0]):
        fail(f"{w.name} {label}: not one line '{w.line}...' on stderr: {err[:300]!r}")
    elif needle and needle not in err:
        fail(f"{w.name} {label}: {needle!r} not in {err.strip()!r}")


def size_limits(w, work, new):
    """A full disk: every limit below the largest output fails cleanly."""
    biggest = max(len(b) for b in new.values())
    for limit in sorted({0, 1, 4096, biggest // 2, biggest - 1} - {b for b in [4096] if b >= biggest}):
        for old in (True, False):
            d = os.path.join(work, "fsize")
            shutil.rmtree(d, ignore_errors=True)
            w.setup(d, old)
            r = run(w.argv, d, limit=limit, env=w.env)
            label = f"file size limit {limit} ({'over an old OUT' if old else 'no OUT'})"
            one_line(w, r, label, "File too large")
            check_outs(w, d, new, label, old_present=old)
            if not old and any(os.path.exists(os.path.join(d, o)) for o in w.outs[:1]):
                fail(f"{w.name} {label}: a failed run made OUT")
            extra = leftovers(w, d)
            if extra:
                fail(f"{w.name} {label}: left {extra}")


def kills(w, work, new, seconds):
    """SIGKILL at random instants of the run; each time OUT old or new, a
    leftover only a killed run's whole hidden temporary, all swept by the
    next run that gets going."""
    d = os.path.join(work, "kill")
    shutil.rmtree(d, ignore_errors=True)
    w.setup(d, True)
    killed = set()
    for i in range(KILLS):
        p = subprocess.Popen(w.argv, cwd=d, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL, env=w.env)
        time.sleep(rng.uniform(0, seconds * 1.1))
        p.send_signal(signal.SIGKILL)
        p.wait()
        killed.add(p.pid)
        check_outs(w, d, new, f"kill {i}")
        for n in leftovers(w, d):
            m = TEMP.match(n)
            if not m or m.group(1) not in w.outs:
                fail(f"{w.name} kill {i}: left {n}, not a hidden temporary of an OUT")
            elif int(m.group(2)) not in killed:
                fail(f"{w.name} kill {i}: {n} is not a killed run's")
            elif read(os.path.join(d, n)) != new[m.group(1)]:
                fail(f"{w.name} kill {i}: {n} is a partial file")
    # a dead writer's leftover is swept, a live one's (this script's) kept
    dead = subprocess.Popen(["true"])
    dead.wait()
    dead_tmp = f".{w.outs[0]}.{dead.pid}.0123456789ab.tmp"
    live_tmp = f".{w.outs[0]}.{os.getpid()}.0123456789ab.tmp"
    for n in (dead_tmp, live_tmp):
        with open(os.path.join(d, n), "wb") as f:
            f.write(b"partial")
    r = run(w.argv, d, env=w.env)
    if os.path.exists(os.path.join(d, dead_tmp)):
        fail(f"{w.name}: a dead writer's temporary file was not swept")
    if not os.path.exists(os.path.join(d, live_tmp)):
        fail(f"{w.name}: a live writer's temporary file was swept")
    else:
        os.unlink(os.path.join(d, live_tmp))
    if r.returncode != 0:
        fail(f"{w.name} after the kills: exit {r.returncode}: {r.stderr[:200]!r}")
    check_outs(w, d, new, "after the kills")
    for o in w.outs:
        if read(os.path.join(d, o)) != new[o]:
            fail(f"{w.name} after the kills: {o} is not the new output")
    extra = leftovers(w, d)
    if extra:
        fail(f"{w.name} after the kills: the next run left {extra}")


def read_only(w, work, new, as_user):
    """A directory the writer may not write to."""
    d = os.path.join(work, "ro")
    shutil.rmtree(d, ignore_errors=True)
    w.setup(d, True)
    os.chmod(d, 0o555)
    try:
        r = run(w.argv, d, user=as_user, env=w.env)
    finally:
        os.chmod(d, 0o755)
    one_line(w, r, "read-only directory", "Permission denied")
    check_outs(w, d, new, "read-only directory")
    for o in w.outs:
        if read(os.path.join(d, o)) != w.old:
            fail(f"{w.name} read-only directory: {o} changed")
    extra = leftovers(w, d)
    if extra:
        fail(f"{w.name} read-only directory: left {extra}")


def gdal_writer(base, pack, src):
    """ogr2ogr -f HPFC through the build's plugin, over an old .hpfc of
    another map; None (after saying why) without the plugin or ogr2ogr."""
    plugin_dir = os.environ.get("HPFC_GDAL_DRIVER_PATH", "")
    ogr2ogr = shutil.which("ogr2ogr")
    if not os.path.isfile(os.path.join(plugin_dir, "ogr_HPFC.so")) or not ogr2ogr:
        print("ogr2ogr -f HPFC: no GDAL driver built or no ogr2ogr, not tested")
        return None
    env = dict(os.environ, GDAL_DRIVER_PATH=plugin_dir)
    # ogr2ogr is not sanitized, the plugin may be: its runtimes go first,
    # and GDAL keeps memory to its end by design (no leak check)
    if os.environ.get("HPFC_GDAL_PRELOAD"):
        env.update(LD_PRELOAD=os.environ["HPFC_GDAL_PRELOAD"],
                   ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:verify_asan_link_order=0",
                   UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1")
    other = os.path.join(TESTS, "data", "gis", "ok", "lines_crossing.geojson")
    old = os.path.join(base, "old.hpfc")
    r = run([pack, "-q", other, "-o", old], base)
    assert r.returncode == 0, r.stderr
    return Writer("ogr2ogr -f HPFC", [ogr2ogr, "-f", "HPFC", "o.hpfc", os.path.basename(src)],
                  ["o.hpfc"], [src], old=read(old), env=env, line=GDAL_LINE)


def main():
    work = tempfile.mkdtemp(prefix="hpfc-faults.")
    os.chmod(work, 0o755)
    try:
        pack = os.path.abspath(PACK)
        inspect = os.path.abspath(INSPECT)
        pfc = os.path.join(ROOT, "data", "delaunay-4000.pfc")
        base = os.path.join(work, "base")
        os.makedirs(base)
        map_ = os.path.join(base, "map.hpfc")
        r = run([pack, "-q", pfc, "-o", map_], base)
        assert r.returncode == 0, r.stderr
        writers = [
            Writer("hpfc-pack", [pack, "-q", "--force", "delaunay-4000.pfc", "-o", "out.hpfc"],
                   ["out.hpfc"], [pfc]),
            Writer("--export-graph", [inspect, "--force", "--export-graph", "g.json", "map.hpfc"],
                   ["g.json"], [map_]),
            Writer("--render svg", [inspect, "--force", "--render", "m.svg", "map.hpfc"],
                   ["m.svg"], [map_]),
        ]
        probe = run([inspect, "--render", os.path.join(base, "p.png"), map_], base)
        if probe.returncode == 0:
            writers.append(Writer("--render png", [inspect, "--force", "--render", "m.png",
                                                   "map.hpfc"], ["m.png", "m.pgw"], [map_]))
        else:
            print("--render png: no cairo, not tested")
        gis_src = os.path.join(TESTS, "data", "gis", "ok", "duplicate_borders.geojson")
        gis = os.path.join(base, "gis.hpfc")
        if run([pack, "-q", gis_src, "-o", gis], base).returncode == 0:
            for ext in ("geojson", "fgb"):
                writers.append(Writer(f"--export {ext}", [inspect, "--force", "--export",
                                                          f"e.{ext}", "gis.hpfc"],
                                      [f"e.{ext}"], [gis]))
            w = gdal_writer(base, pack, os.path.join(TESTS, "data", "gis", "counties_ne.geojson"))
            if w:
                writers.append(w)
        else:
            print("--export: GIS not built in, not tested")
        # whom the read-only directory stops: root writes anywhere, so the
        # run drops to nobody when the test runs as root
        as_user = None
        if os.geteuid() == 0:
            as_user = 65534
            if run(["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups",
                    inspect, "--help"], work).returncode != 0:
                as_user = -1
        for w in writers:
            d = os.path.join(work, "clean-" + w.name.replace(" ", "_").strip("-"))
            w.setup(d, False)
            t0 = time.monotonic()
            r = run(w.argv, d, env=w.env)
            seconds = time.monotonic() - t0
            if r.returncode != 0:
                fail(f"{w.name}: the undisturbed run failed: {r.stderr[:300]!r}")
                continue
            new = {o: read(os.path.join(d, o)) for o in w.outs}
            r = run(w.argv, d, env=w.env)
            if any(read(os.path.join(d, o)) != new[o] for o in w.outs):
                print(f"{w.name}: output differs from run to run; not tested")
                continue
            size_limits(w, work, new)
            kills(w, work, new, seconds)
            if as_user == -1:
                print(f"{w.name}: read-only directory not tested (cannot drop root)")
            else:
                read_only(w, work, new, as_user)
            print(f"{w.name}: checked ({sum(map(len, new.values()))} bytes, run {seconds:.2f} s)")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if failures:
        print(f"{len(failures)} check(s) failed")
        sys.exit(1)
    print("all checks passed")


main()
