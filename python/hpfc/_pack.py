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

A .pfc graph is read by the workers, a chunk of its text each, into one
graph file in the shared directory (hpfc.h, "A .pfc read in chunks, into a
graph file"); this process maps that file to cut the parts and, for GEOM,
to write the joined file: the graph lives in the page cache, not in the
client. Any other input (GIS layers, Draco meshes), or any hpfc-pack
`options`, goes through hpfc-pack --parts-dir, which reads, nodes and
projects the input once, as hpfc-pack alone does (GEOS's noding and the
linking of features to faces see the whole layer), cuts the parts for the
workers and joins what they built (with the features, attributes and edge
links of a GIS layer). The graph is validated part by part on the workers
(every flaw but a vertex of no edge lies in one root pixel, whose part
holds every edge through it); after a chunk or a part finds one, the whole
text is read and validated once to report it as hpfc-pack does.
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


# a .pfc is read by the workers in chunks of about this many bytes (at
# least one chunk a worker)
CHUNK_BYTES = 64 << 20


def _returning_errors(call, *args):
    """call(*args) on a worker, an hpfc.Error returned rather than raised:
    a flaw of the input is an answer, not a task's failure for Dask to log
    on the worker's standard error."""
    try:
        return call(*args)
    except Error as e:
        return e


def _scan_chunk(path, begin, end):
    """One chunk of the .pfc scanned, on a worker: its counts and digits."""
    return _returning_errors(_hpfc._pfc_scan, path, begin, end)


def _fill_chunk(path, begin, end, scan, graph, totals, digits, firsts):
    """One chunk of the .pfc filled into its stretch of DIR/graph, on a
    worker: its points' box, or None."""
    return _returning_errors(_hpfc._pfc_fill, path, begin, end, scan, graph, totals, digits, firsts)


def _gather_all(c, futures, stage):
    """The tasks' results, drawn on the bar as they come, once every task
    is done (none still writing into the directory the caller removes
    next); the first hpfc.Error one returned is raised."""
    if sys.stderr.isatty():
        from dask.distributed import as_completed
        _progress(stage, 0, len(futures))
        for done, _ in enumerate(as_completed(futures), 1):
            _progress(stage, done, len(futures))
        _progress(None)
    results = c.gather(futures)
    for r in results:
        if isinstance(r, Error):
            raise r
    return results


def _route_chunk(directory, plan, chunk, first_edge, end_edge):
    """One chunk's edges routed to the parts, on a worker: DIR/route-C."""
    return _returning_errors(_hpfc._pfc_route, directory, plan, chunk, first_edge, end_edge)


def _build_routed_part(directory, plan, k, chunks):
    """One part built from DIR/graph and its edges in the route files, on a
    worker (its path, or the hpfc.Error that refused it)."""
    return _returning_errors(_hpfc._pack_part_routed, directory, plan, k, chunks)


def _read_pfc(c, path, directory, chunks):
    """The .pfc read by the cluster's workers into the graph file
    DIR/graph, a chunk a task (hpfc.h, "A .pfc read in chunks"), the
    client holding only the chunks' counts. Returns the chunks' edge
    ranges and their points' box. A flaw a
    chunk finds, or one that needs the whole text (more than 30 digits, no
    edge), is reworded by reading the whole text here, as hpfc-pack would."""
    if chunks is None:
        n = max(1, len(c.scheduler_info()["workers"]))
        chunks = max(n, -(-os.path.getsize(path) // CHUNK_BYTES))
    bounds = _hpfc._pfc_chunks(path, int(chunks))
    try:
        scans = _gather_all(c, [c.submit(_scan_chunk, path, b, e, pure=False) for b, e in bounds],
                            "reading")
        digits = max(s[3] for s in scans)
        totals = tuple(sum(s[k] for s in scans) for k in range(3))
        if totals[1] == 0:  # reworded below, with the line hpfc-pack names
            raise Error(26, "HPFC_E_EMPTY", "no edge", path)
        if digits > 30:
            raise Error(28, "HPFC_E_LIMIT", "more than 30 fractional digits", path)
        graph = os.path.join(directory, "graph")
        _hpfc._graph_create(graph, totals[0], totals[1], totals[2], -digits)
        firsts, futures, ranges = [0, 0, 0], [], []
        for (b, e), scan in zip(bounds, scans):
            futures.append(c.submit(_fill_chunk, path, b, e, scan, graph, totals, digits,
                                    tuple(firsts), pure=False))
            ranges.append((firsts[1], firsts[1] + scan[1]))
            firsts = [firsts[k] + scan[k] for k in range(3)]
        boxes = [b for b in _gather_all(c, futures, "reading") if b is not None]
        box = (min(b[0] for b in boxes), min(b[1] for b in boxes), max(b[2] for b in boxes),
               max(b[3] for b in boxes))
        return ranges, box
    except Error as e:
        # the flaw in hpfc-pack's words, from the whole text
        _hpfc._pack_check(os.fspath(path))
        raise e


def _build_part(directory, plan, k):
    """One part, on a worker: DIR/part-K.pfc and .ids to DIR/part-K.part
    (its path, or the hpfc.Error that refused it)."""
    return _returning_errors(_hpfc._pack_part, directory, plan, k)


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


class _Cluster:
    """The caller's client, or a LocalCluster of `workers` processes for
    the call, closed on leaving."""

    def __init__(self, client, workers):
        self.client, self.workers, self.cluster = client, workers, None

    def __enter__(self):
        if self.client is not None:
            return self.client
        from dask.distributed import Client, LocalCluster
        self.cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True,
                                    dashboard_address=":0")
        self.client = Client(self.cluster)
        return self.client

    def __exit__(self, *exc):
        if self.cluster is not None:
            self.client.close()
            self.cluster.close()


def _build_parts(c, futures):
    """Every part built on the cluster (the futures of their tasks): their
    part files' paths, or the first hpfc.Error a part raised."""
    try:
        return _gather_all(c, futures, "parts"), None
    except Error as e:
        return None, e


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


def _read_range(tool, options, source, directory, k, rng, tag):
    """Range K of a GIS input's features read on a worker by hpfc-pack
    --read-range into DIR/range-K: None, or hpfc-pack's message."""
    layer, begin, end = rng
    out = os.path.join(directory, "range-%d" % k)
    proc = subprocess.run([tool, "-q", "--read-range", "%d:%d:%s" % (layer, begin, "end" if end < 0 else end),
                           "--range-tag", tag] + options + ["-o", out, "--", source],
                          stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    if proc.returncode == 0:
        return None
    lines = [ln for ln in proc.stderr.decode("utf-8", "replace").splitlines() if ln.strip()]
    return "range %d: %s" % (k, lines[-1] if lines else "hpfc-pack exit status %d" % proc.returncode)


def _read_ranges(c, tool, read, directory, ranges, tag):
    """The features' ranges read by the workers: None, or the first
    failure's message (the features are then read by hpfc-pack)."""
    options, source = read
    futures = [c.submit(_read_range, tool, options, source, directory, k, rng, tag, pure=False)
               for k, rng in enumerate(ranges)]
    failures = [f for f in _gather_all(c, futures, "reading") if f]
    return failures[0] if failures else None


def _pack_through_tool(tool, args, client, workers, directory, read=None):
    """hpfc-pack --parts-dir as a co-process: it reads and cuts, prints the
    plan, the cluster builds the parts, and a line on its standard input
    ('built' or 'failed') lets it join them and write the file. With
    `read` (options, input), hpfc-pack first prints the ranges of a GIS
    input's features, which the workers read (_read_range) before a line
    'read' or 'failed' lets it go on."""
    with tempfile.TemporaryFile() as err, _Cluster(client, workers) as c:
        # not -q: its notes (a guessed SRS, ...) are passed on; its report,
        # after the plan on standard output, is read and dropped
        proc = subprocess.Popen([tool, "--parts-dir", directory] + args,
                                stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=err)
        range_failure = None
        try:
            line = proc.stdout.readline()
            first = json.loads(line) if line else None
            if first is not None and "ranges" in first:
                range_failure = _read_ranges(c, tool, read, directory, first["ranges"], first["tag"])
                proc.stdin.write(b"failed\n" if range_failure else b"read\n")
                proc.stdin.flush()
                line = proc.stdout.readline()
            if line:
                plan = json.loads(line)
                _paths, failure = _build_parts(c, [c.submit(_build_part, directory, plan, k, pure=False)
                                                   for k in range(plan["parts"])])
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
        if range_failure:  # the input was good, but read by one process
            sys.stderr.write("hpfc.pack: note: the features were read by hpfc-pack alone (%s)\n"
                             % range_failure)


def _size_arg(pair):
    return "%dx%d" % pair


def pack(input, output, *, client=None, partitions=None, workers=2, root=64, refine=2,  # noqa: A002
         leaf_points=16, layout="compact", labels=True, geometry=True, shared_dir=None,
         options=(), hpfc_pack=None, read_on_workers=True, chunks=None, ranges=None):
    """Packs `input` into `output` in `partitions` parts (default: four a
    worker), built on the Dask `client`'s workers (None: a LocalCluster of
    `workers` processes for this call). Options as hpfc-pack's --root,
    --refine, --leaf-points, --layout, --no-labels and --no-geometry; any
    other hpfc-pack option in `options` (["--fields", "all"], ...). The
    file is the one hpfc-pack writes with the same options.

    A .pfc input without `options` is read by the workers, each a chunk of
    about CHUNK_BYTES (or `chunks` chunks), into one graph file in the
    shared directory, which this process then maps rather than holds: the
    input must be readable at the same path on every worker, as
    `shared_dir` is (`read_on_workers=False` reads it here). Any other
    input goes through hpfc-pack (`hpfc_pack`, else $HPFC_PACK, else
    PATH), which the workers also run to read a GIS layer's features, in
    `ranges` runs (default: one a worker) by GDAL's feature order, before
    hpfc-pack projects and nodes them as a whole (`read_on_workers=False`:
    hpfc-pack reads them too); the input and hpfc-pack must then be at the
    same paths on every worker. Raises hpfc.Error (the input, a part;
    hpfc-pack's exit status and message as code and text), ValueError (an
    option) or OSError."""
    root_cols, root_rows = _sizes(root, 1, "root")
    cols, rows = _sizes(refine, 2, "refine")
    if layout not in LAYOUTS:
        raise ValueError("layout: compact or paper")
    if leaf_points < 0:
        raise ValueError("leaf_points: 0 (no bound) or more")
    if ranges is not None and not 1 <= int(ranges) <= 1 << 20:
        raise ValueError("ranges: 1 to 1048576")
    n = workers if client is None else len(client.scheduler_info()["workers"])
    if partitions is None:
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
            read = None
            if read_on_workers:
                args += ["--read-ranges", str(int(ranges) if ranges else min(max(1, n), 1 << 20))]
                # a file at the same path on every worker; any other GDAL
                # name (PG:..., /vsicurl/...) as given
                source = os.fspath(input)
                read = (options, os.path.abspath(source) if os.path.exists(source) else source)
            _pack_through_tool(tool, args + options + ["-o", os.fspath(output), "--",
                               os.fspath(input)], client, workers, tmp, read)
            return
        source = os.fspath(input)
        with _Cluster(client, workers) as c:
            if read_on_workers:
                chunk_edges, box = _read_pfc(c, source, tmp, chunks)
                source = os.path.join(tmp, "graph")
            try:
                _progress("cutting")
                if read_on_workers:
                    plan = _hpfc._pack_plan(source, root_cols, root_rows, cols, rows, int(leaf_points),
                                            partitions, box)
                else:
                    plan = _hpfc._pack_cut(source, tmp, root_cols, root_rows, cols, rows,
                                           int(leaf_points), partitions)
            except Error:
                # a flaw of the whole graph (a vertex of no edge) seen in
                # the graph file, which has no lines: in hpfc-pack's words
                # (_pack_cut read the text itself and words it so already)
                if read_on_workers:
                    _hpfc._pack_check(os.fspath(input))
                raise
            finally:
                _progress(None)
            if read_on_workers:
                # each chunk's edges routed to the parts by a worker, each
                # part's graph copied out of the graph file by its builder
                _gather_all(c, [c.submit(_route_chunk, tmp, plan, k, e0, e1, pure=False)
                                for k, (e0, e1) in enumerate(chunk_edges)], "routing")
                futures = [c.submit(_build_routed_part, tmp, plan, k, len(chunk_edges), pure=False)
                           for k in range(plan["parts"])]
            else:
                futures = [c.submit(_build_part, tmp, plan, k, pure=False) for k in range(plan["parts"])]
            paths, failure = _build_parts(c, futures)
        if failure:
            # a part found a flaw of the graph, in its own numbering:
            # the whole graph's check words it as hpfc-pack does
            _hpfc._pack_check(os.fspath(input))
            raise failure
        _progress("joining")
        try:
            _hpfc._pack_merge(list(paths), source, os.fspath(output), LAYOUTS[layout],
                              bool(labels), bool(geometry), read_on_workers)
        finally:
            _progress(None)
