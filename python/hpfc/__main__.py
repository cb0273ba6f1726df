"""python3 -m hpfc pack INPUT -o OUTPUT.hpfc [--workers N | --scheduler ADDRESS]
[--partitions N] [--root N|NxM] [--refine N|NxM] [--leaf-points N]
[--layout compact|paper] [--no-labels] [--no-geometry] [--shared-dir DIR]
[--read-here] [--ranges N] [-- HPFC-PACK-OPTION...]

Packs a map in parts on Dask (hpfc.pack): a LocalCluster of N workers
(default 2), or the cluster whose scheduler is at ADDRESS (started with
`dask scheduler` and `dask worker ADDRESS`, which must see --shared-dir).
INPUT is anything hpfc-pack reads: a .pfc graph is read by the workers (at
the same path: --read-here reads it here) and cut here, other inputs
(GIS layers, Draco meshes) and the hpfc-pack options after `--`
(-- --fields all --vertices all, ...) go through hpfc-pack --parts-dir ($HPFC_PACK, else
PATH); a GIS layer's features are read by the workers in N ranges
(default: one a worker; --read-here: by hpfc-pack) and noded and
projected by hpfc-pack. The file is hpfc-pack's with the same options. One line on stderr
and exit status 1 on failure, 2 on a usage error."""
import argparse
import sys

from . import Error
from ._pack import pack


def _size(text):
    parts = text.lower().split("x")
    if len(parts) > 2 or not all(p.isdigit() for p in parts):
        raise argparse.ArgumentTypeError("N or NxM")
    return (int(parts[0]), int(parts[-1]))


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m hpfc", description=__doc__.split("\n\n")[1])
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("pack", help="pack a map in parts on Dask")
    p.add_argument("input")
    p.add_argument("-o", "--output", required=True)
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=2, help="LocalCluster workers (default 2)")
    where.add_argument("--scheduler", help="a running cluster's scheduler, tcp://HOST:PORT")
    p.add_argument("--partitions", type=int, help="parts (default: four a worker)")
    p.add_argument("--root", type=_size, default=(64, 64))
    p.add_argument("--refine", type=_size, default=(2, 2))
    p.add_argument("--leaf-points", type=int, default=16)
    p.add_argument("--layout", choices=("compact", "paper"), default="compact")
    p.add_argument("--no-labels", action="store_true")
    p.add_argument("--no-geometry", action="store_true")
    p.add_argument("--shared-dir", help="where the parts' files go (default: beside OUTPUT)")
    p.add_argument("--read-here", action="store_true",
                   help="read a .pfc INPUT in this process, and a GIS layer's features in hpfc-pack, "
                        "not on the workers (which must see INPUT's path)")
    p.add_argument("--ranges", type=int, help="GIS input: feature ranges the workers read "
                                              "(default: one a worker)")
    argv = list(sys.argv[1:] if argv is None else argv)
    cut = argv.index("--") if "--" in argv else len(argv)
    args = parser.parse_args(argv[:cut])
    options = argv[cut + 1:]
    client = None
    try:
        if args.scheduler:
            from dask.distributed import Client
            client = Client(args.scheduler)
        pack(args.input, args.output, client=client, partitions=args.partitions,
             workers=args.workers, root=args.root, refine=args.refine,
             leaf_points=args.leaf_points, layout=args.layout, labels=not args.no_labels,
             geometry=not args.no_geometry, shared_dir=args.shared_dir, options=options,
             read_on_workers=not args.read_here, ranges=args.ranges)
    except (Error, ValueError, OSError) as e:
        print("python3 -m hpfc pack: %s" % e, file=sys.stderr)
        return 1
    finally:
        if client is not None:
            client.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
