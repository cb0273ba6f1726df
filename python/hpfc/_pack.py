"""hpfc.pack: a .pfc graph packed in parts on a Dask cluster.

The library builds a map in parts, each a run of root pixels, and joins
them into the very tree (and file) a single build gives
(spec/part-format.md, hpfc.h "A build split into parts"). Here the client
reads the graph once and cuts each part's graph into a shared directory,
the workers build the parts into part files, and the client joins them and
writes the file atomically. The output is byte for byte hpfc-pack's with
the same options.

    import hpfc
    from dask.distributed import Client
    hpfc.pack("streets.pfc", "streets.hpfc", client=Client("tcp://host:8786"),
              partitions=64, shared_dir="/mnt/shared/tmp")

Without a client, a LocalCluster of `workers` processes (default 2) runs
for the call. The parts' files live in `shared_dir` (default: a temporary
directory beside the output), which every worker must see.

First step of issue 32: .pfc input only (GIS layers go through hpfc-pack);
the client still holds the whole graph while it cuts the parts and the
joined tree while it writes. The graph is validated part by part on the
workers (every flaw but a vertex of no edge lies in one root pixel, whose
part holds every edge through it); after a part finds one, the client
validates the whole graph once to report it as hpfc-pack does.
"""
import os
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


def _build_part(part_pfc, part_ids, out, plan, params, k):
    """One part, on a worker: the part's graph files to its part file."""
    x0, y0, width, height, depth, unit, edges, parts = plan
    root_cols, root_rows, cols, rows, leaf_points = params
    return _hpfc._pack_part(part_pfc, part_ids, out, unit, edges, x0, y0, width, height, depth,
                            root_cols, root_rows, cols, rows, leaf_points, k, parts)


def pack(input, output, *, client=None, partitions=None, workers=2, root=64, refine=2,  # noqa: A002
         leaf_points=16, layout="compact", labels=True, geometry=True, shared_dir=None):
    """Packs the .pfc graph `input` into `output` in `partitions` parts (default:
    four a worker), built on the Dask `client`'s workers (None: a LocalCluster
    of `workers` processes for this call). Options as hpfc-pack's --root,
    --refine, --leaf-points, --layout, --no-labels and --no-geometry; the file
    is the one hpfc-pack writes with them. Raises hpfc.Error (the input, a
    part) or ValueError (an option)."""
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
    params = (root_cols, root_rows, cols, rows, int(leaf_points))
    with tempfile.TemporaryDirectory(prefix=".hpfc-parts.", dir=where) as tmp:
        # the input read and cut first: a bad one fails before any cluster starts
        plan = _hpfc._pack_cut(os.fspath(input), tmp, *params, partitions)
        cluster = None
        if client is None:
            from dask.distributed import Client, LocalCluster
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=":0")
        try:
            c = client or Client(cluster)
            futures = [c.submit(_build_part, os.path.join(tmp, "part-%d.pfc" % k),
                                os.path.join(tmp, "part-%d.ids" % k),
                                os.path.join(tmp, "part-%d.part" % k), plan, params, k, pure=False)
                       for k in range(plan[7])]
            try:
                paths = c.gather(futures)
            except Error:
                # a part found a flaw of the graph, in its own numbering:
                # the whole graph's check words it as hpfc-pack does
                _hpfc._pack_check(os.fspath(input))
                raise
        finally:
            if cluster is not None:
                c.close()
                cluster.close()
        _hpfc._pack_merge(list(paths), os.fspath(input), os.fspath(output), LAYOUTS[layout],
                          bool(labels), bool(geometry))
