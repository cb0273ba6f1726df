"""hpfc.pack: a map packed in parts on a Dask cluster.

The library builds a map in parts, each a run of root pixels, and joins
them into the very tree (and file) a single build gives
(spec/part-format.md, hpfc.h "A build split into parts"). The parts'
graphs are cut into a shared directory, the workers build the parts into
part files, and the parts are joined and the file written atomically
(docs/interfaces.md section 8). The output is byte for byte hpfc-pack's
with the same options.

    import hpfc
    from dask.distributed import Client
    hpfc.pack("streets.pfc", "streets.hpfc", client=Client("tcp://host:8786"),
              partitions=64, shared_dir="/mnt/shared/tmp")
    hpfc.pack("counties.gpkg", "counties.hpfc", options=["--fields", "all"])

Without a client, a LocalCluster of `workers` processes (default 2) runs
for the call. The parts' files live in `shared_dir` (default: a temporary
directory beside the output), which every worker must see.

A .pfc graph is read, cut and joined in this process. Any other input (GIS
layers, Draco meshes), or any hpfc-pack `options`, goes through hpfc-pack
--parts-dir, which reads, nodes and projects the input once, as hpfc-pack
alone does, cuts the parts for the workers and joins what they built (with
the features, attributes and edge links of a GIS layer); reading the input
in parallel is not done yet. The client holds the whole graph while it cuts
the parts and the joined tree while it writes. The graph is validated part
by part on the workers (every flaw but a vertex of no edge lies in one root
pixel, whose part holds every edge through it); after a part finds one,
the whole graph is validated once to report it as hpfc-pack does.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

from . import _hpfc
from ._errors import Error

LAYOUTS = {"compact": 2, "paper": 1}


def _sizes(value, least, what):
    if isinstance(value, int):
        value = (value, value)
    cols, rows = (int(v) for v in value)
    if cols < least or rows < least:
        raise ValueError("%s: each side at least %d" % (what, least))
    return cols, rows


def _build_part(directory, plan, k):
    """One part, on a worker: DIR/part-K.pfc and .ids to DIR/part-K.part."""
    return _hpfc._pack_part(directory, plan, k)


def _is_pfc(path):
    """What hpfc-pack reads as .pfc: the suffix, or a first record 'pfc'."""
    if str(path).endswith(".pfc"):
        return True
    try:
        with open(path, "rb") as f:
            return f.read(4) in (b"pfc ", b"pfc\t", b"pfc\n")
    except OSError:
        return False


def _progress(stage, done=None, total=None):
    """hpfc-pack's bar, on standard error when it is a terminal:
    "hpfc: STAGE [####......]  40%", or the stage alone; None clears it."""
    if not sys.stderr.isatty():
        return
    if stage is None:
        sys.stderr.write("\r\033[K")
    elif total:
        n = int(30 * done / total)
        sys.stderr.write("\rhpfc: %-10s [%s] %3d%%\033[K" % (stage, "#" * n + "." * (30 - n),
                                                            100 * done // total))
    else:
        sys.stderr.write("\rhpfc: %-10s ...\033[K" % stage)
    sys.stderr.flush()


def _await_parts(futures):
    """Draws the parts done until every one is (or failed)."""
    if not sys.stderr.isatty():
        return
    from dask.distributed import as_completed
    _progress("parts", 0, len(futures))
    for done, _ in enumerate(as_completed(futures), 1):
        _progress("parts", done, len(futures))
    _progress(None)


def _build_parts(client, workers, directory, plan):
    """Every part built on the cluster (a LocalCluster of `workers` for the
    call when client is None): their part files' paths, or the first
    hpfc.Error a part raised."""
    cluster = None
    if client is None:
        from dask.distributed import Client, LocalCluster
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=":0")
    c = client or Client(cluster)
    try:
        futures = [c.submit(_build_part, directory, plan, k, pure=False)
                   for k in range(plan["parts"])]
        _await_parts(futures)
        try:
            return c.gather(futures), None
        except Error as e:
            # gather raises at the first failed part while the others run
            # on, writing into the directory the caller removes next: all
            # of them done (or failed) first
            from dask.distributed import wait
            wait(futures)
            return None, e
    finally:
        if cluster is not None:
            c.close()
            cluster.close()


def _find_hpfc_pack(given):
    path = given or os.environ.get("HPFC_PACK") or shutil.which("hpfc-pack")
    if not path:
        raise FileNotFoundError("hpfc-pack not found (set HPFC_PACK, or put it on PATH): "
                                "inputs other than .pfc are read by hpfc-pack --parts-dir")
    return path


def _last_line(stream):
    stream.seek(0)
    lines = [ln for ln in stream.read().decode("utf-8", "replace").splitlines() if ln.strip()]
    return lines[-1] if lines else "no message"


def _pack_through_tool(tool, args, client, workers, directory):
    """hpfc-pack --parts-dir as a co-process: it reads and cuts, prints the
    plan, the cluster builds the parts, and a line on its standard input
    ('built' or 'failed') lets it join them and write the file."""
    with tempfile.TemporaryFile() as err:
        # not -q: its notes (a guessed SRS, ...) are passed on; its report,
        # after the plan on standard output, is read and dropped
        proc = subprocess.Popen([tool, "--parts-dir", directory] + args,
                                stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=err)
        try:
            line = proc.stdout.readline()
            if line:
                _paths, failure = _build_parts(client, workers, directory, json.loads(line))
                proc.stdin.write(b"failed\n" if failure else b"built\n")
                proc.stdin.close()
                if not failure:
                    _progress("joining")
                proc.stdout.read()
            rc = proc.wait()
            _progress(None)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
        if rc != 0:
            text = _last_line(err)
            if text.startswith("hpfc-pack: "):
                text = text[len("hpfc-pack: "):]
            raise Error(rc, "hpfc-pack exit status", text)
        err.seek(0)
        warnings = err.read()
        if warnings:  # what hpfc-pack says of the input (a guessed SRS, ...)
            sys.stderr.write(warnings.decode("utf-8", "replace"))


def _size_arg(pair):
    return "%dx%d" % pair


def pack(input, output, *, client=None, partitions=None, workers=2, root=64, refine=2,  # noqa: A002
         leaf_points=16, layout="compact", labels=True, geometry=True, shared_dir=None,
         options=(), hpfc_pack=None):
    """Packs `input` into `output` in `partitions` parts (default: four a
    worker), built on the Dask `client`'s workers (None: a LocalCluster of
    `workers` processes for this call). Options as hpfc-pack's --root,
    --refine, --leaf-points, --layout, --no-labels and --no-geometry; any
    other hpfc-pack option in `options` (["--fields", "all"], ...). The
    file is the one hpfc-pack writes with the same options.

    A .pfc input without `options` is read here; any other goes through
    hpfc-pack (`hpfc_pack`, else $HPFC_PACK, else PATH). Raises hpfc.Error
    (the input, a part; hpfc-pack's exit status and message as code and
    text), ValueError (an option) or OSError."""
    root_cols, root_rows = _sizes(root, 1, "root")
    cols, rows = _sizes(refine, 2, "refine")
    if layout not in LAYOUTS:
        raise ValueError("layout: compact or paper")
    if leaf_points < 0:
        raise ValueError("leaf_points: 0 (no bound) or more")
    if partitions is None:
        n = workers if client is None else len(client.scheduler_info()["workers"])
        partitions = 4 * max(1, n)
    partitions = max(1, min(int(partitions), root_cols * root_rows))
    where = shared_dir or os.path.dirname(os.path.abspath(output))
    options = [str(o) for o in options]
    tool = None if _is_pfc(input) and not options else _find_hpfc_pack(hpfc_pack)
    with tempfile.TemporaryDirectory(prefix=".hpfc-parts.", dir=where) as tmp:
        if tool:
            args = ["--partitions", str(partitions), "--root", _size_arg((root_cols, root_rows)),
                    "--refine", _size_arg((cols, rows)), "--leaf-points", str(int(leaf_points)),
                    "--layout", layout]
            args += [] if labels else ["--no-labels"]
            args += [] if geometry else ["--no-geometry"]
            _pack_through_tool(tool, args + options + ["-o", os.fspath(output), "--",
                               os.fspath(input)], client, workers, tmp)
            return
        # the input read and cut first: a bad one fails before any cluster starts
        plan = _hpfc._pack_cut(os.fspath(input), tmp, root_cols, root_rows, cols, rows,
                               int(leaf_points), partitions)
        paths, failure = _build_parts(client, workers, tmp, plan)
        if failure:
            # a part found a flaw of the graph, in its own numbering:
            # the whole graph's check words it as hpfc-pack does
            _hpfc._pack_check(os.fspath(input))
            raise failure
        _progress("joining")
        try:
            _hpfc._pack_merge(list(paths), os.fspath(input), os.fspath(output), LAYOUTS[layout],
                              bool(labels), bool(geometry))
        finally:
            _progress(None)
