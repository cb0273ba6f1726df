#!/usr/bin/env python3
"""How the time and memory of every whole-file call grow with the map
(bench/README.md, "Scaling"). Run through bench/run-scaling.sh, which builds
the programs and fetches the public layers.

    scaling.py full BUILD DATA [--record]
    scaling.py smoke BUILD DATA [--record]

full: three maps of each kind (series), every stage timed (CPU and wall
seconds, peak RSS), the exponent between consecutive sizes,
log(t2 / t1) / log(n2 / n1) with n the shape points read, flagged ('!')
above 1.2; then hpfc-inspect --export against ogr2ogr on the largest public
layer. Tables on stdout, everything in DATA/results-full.json.

smoke: two small generated maps, every stage counted in instructions by
callgrind (deterministic), their exponents compared with those recorded
in bench/scaling-exponents.json: a stage whose exponent exceeds its
recorded one by more than the file's margin fails, named with the growth.

--record writes the exponents measured into bench/scaling-exponents.json.
"""
import json
import math
import os
import random
import re
import statistics
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
RECORD = os.path.join(HERE, "scaling-exponents.json")
FLAG = 1.2  # an exponent above this is flagged

# The series: (name, key field, sizes); a size is (label, how to make its
# FlatGeobuf: ("topojson"|"geojson", npm path, layer) or a generator).
CONTINENT = ("gen_continent.py", 100)  # points per side of a county
PUBLIC = ("public", "name", [
    ("countries-50m", ("topojson", "world-atlas/countries-50m.json", "countries")),
    ("countries-10m", ("topojson", "world-atlas/countries-10m.json", "countries")),
    ("countries-land-1m", ("geojson", "@geo-maps/countries-land-1m/map.geo.json", None)),
])
FULL = [
    PUBLIC,
    ("continent", "id", [("20x12", ("continent", 20, 12)), ("62x39", ("continent", 62, 39)),
                         ("195x122", ("continent", 195, 122))]),
    ("archipelago", None, [("13400", ("archipelago", 13400)), ("134000", ("archipelago", 134000)),
                           ("1342000", ("archipelago", 1342000))]),
]
SMOKE = [("continent", "id", [("9x5", ("continent", 9, 5)), ("20x12", ("continent", 20, 12))])]
KEYS = {"countries-land-1m": "A3"}  # the public layers' key, where not the series'

# Stages: name, and for the smoke the calls whose instructions it counts,
# (caller, callee) pairs of the callgrind profile (caller None: from any).
PACK = [
    ("pack.read", [(None, "read_dataset")]),
    ("pack.project", [(None, "project_and_snap")]),
    ("pack.node", [(None, "node")]),
    ("pack.graph", [(None, "segment_graph_make")]),
    ("pack.build", [(None, "hpfc_build_sized")]),
    ("pack.link", [(None, "leaf_crossings_collect"), (None, "gis_features_link_method")]),
    # the faces are numbered once, for LABL, and the linking takes them
    # (hpfc_write_options.faces_out): part of pack.write, from any caller
    # (the writer's own functions are inlined into each other)
    # on as many threads as the machine has cores (hpfc_write_options.threads):
    # the calling thread's share under hpfc_faces_build_threads, the others'
    # under crew_main, which a one-core machine does not start (optional)
    ("pack.faces", [(None, "hpfc_faces_build_threads"), (None, "crew_main", "optional")]),
    ("pack.link.witness", [(None, "face_witnesses")]),
    ("pack.link.topology", [(None, "face_link_run")]),
    ("pack.link.check", [(None, "face_check_create"), (None, "face_check_features")]),
    # the tree to a mapped scratch file, then the final file copied from it
    ("pack.write", [(None, "hpfc_tree_write_fd_sized"), (None, "hpfc_file_write_fd_sized")]),
]
# the report's CPU seconds of each pack stage (write: what is not linking;
# the faces' numbering is in it and has no figure of its own in the report)
PACK_REPORT = {"pack.read": "gis_read", "pack.project": "gis_project", "pack.node": "gis_node",
               "pack.graph": "gis_graph", "pack.build": "build",
               "pack.link.witness": "link_witness", "pack.link.topology": "link_topology",
               "pack.link.check": "link_check", "pack.link": "features"}
CALLS = [
    ("faces", [(None, "hpfc_faces_build")]),
    ("shapes.create", [(None, "hpfc_shapes_create")]),
    ("shapes.largest", [(None, "hpfc_shapes_feature_polygons")]),
    ("shapes.all", [(None, "hpfc_shapes_feature_polygons")]),
    ("export", [(None, "write_features")]),
    ("export-faces", [(None, "write_faces")]),
    ("verify", [(None, "verify_file")]),
    ("render", [(None, "render_file")]),
    ("locate-batch", [(None, "lattice_points"), (None, "hpfc_locate_batch_sized")]),
]


class Tools:
    def __init__(self, build):
        self.pack = os.path.join(build, "hpfc-pack/hpfc-pack")
        self.inspect = os.path.join(build, "hpfc-inspect/hpfc-inspect")
        self.shapes = os.path.join(build, "bench/bench_shapes")
        self.locate = os.path.join(build, "bench/bench_locate_batch")


def timed(cmd, wrap=None):
    """Runs cmd; its stdout and (wall seconds, CPU seconds (user + system,
    wait4's rusage), peak RSS in MiB). The peak is GNU time's: a child's own
    ru_maxrss would count the RSS of this process it was spawned from. wrap
    (valgrind) replaces GNU time, and the peak is then 0."""
    with tempfile.NamedTemporaryFile() as peak, tempfile.TemporaryFile() as err:
        t0 = time.monotonic()
        p = subprocess.Popen((wrap or ["/usr/bin/time", "-f", "%M", "-o", peak.name]) + cmd,
                             stdout=subprocess.PIPE, stderr=err)
        out = p.stdout.read()
        _, status, ru = os.wait4(p.pid, 0)
        wall = time.monotonic() - t0
        p.stdout.close()
        p.returncode = os.waitstatus_to_exitcode(status)  # reaped here, not by Popen
        if p.returncode:
            err.seek(0)
            sys.exit("%s failed (%d): %s" % (" ".join(cmd), p.returncode,
                                             err.read().decode()[-600:]))
        kib = 0 if wrap else int(peak.read().split()[-1])
    return out.decode(), (wall, ru.ru_utime + ru.ru_stime, kib / 1024)


# ---- data ------------------------------------------------------------------


def sh(cmd, env=None):
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, env=env)


def make_source(data, label, how):
    """The size's FlatGeobuf under DATA, made once."""
    out = os.path.join(data, label + ".fgb")
    if os.path.exists(out):
        return out
    tmp = out + ".tmp.fgb"
    if os.path.exists(tmp):
        os.remove(tmp)
    env = dict(os.environ, OGR_GEOJSON_MAX_OBJ_SIZE="0")
    if how[0] in ("topojson", "geojson"):
        src = os.path.join(data, "node_modules", how[1])
        sh(["ogr2ogr", "-f", "FlatGeobuf", tmp, src] + ([how[2]] if how[2] else []), env)
    elif how[0] == "continent":
        gj = out + ".tmp.geojson"
        sh([sys.executable, os.path.join(HERE, CONTINENT[0]), gj, str(how[1]), str(how[2]),
            str(CONTINENT[1])])
        sh(["ogr2ogr", "-f", "FlatGeobuf", tmp, gj], env)
        os.remove(gj)
    else:
        sh([sys.executable, os.path.join(HERE, "gen_archipelago.py"), str(how[1]), tmp])
    os.rename(tmp, out)
    return out


def points_file(data, label, src, n):
    """n random points (seed 36) over the source layer's extent, as
    bench_locate_batch reads them: n x values, then n y values."""
    path = os.path.join(data, "%s.points.f64" % label)
    if os.path.exists(path) and os.path.getsize(path) == 16 * n:
        return path
    from osgeo import ogr
    ds = ogr.Open(src)
    x0, x1, y0, y1 = ds.GetLayer(0).GetExtent()
    ds = None
    rng = random.Random(36)
    with open(path + ".tmp", "wb") as f:
        for lo, hi in ((x0, x1), (y0, y1)):
            f.write(struct.pack("%dd" % n, *(rng.uniform(lo, hi) for _ in range(n))))
    os.rename(path + ".tmp", path)
    return path


# ---- the stages of one map -----------------------------------------------


# the stages whose program reports the call's own time (JSON on stdout)
IN_PROCESS = ("faces", "shapes.all", "shapes.largest", "locate-batch")


def commands(t, packed, out_dir, largest, points, lonlat):
    """Every stage after the pack: name -> command."""
    o = lambda name: os.path.join(out_dir, name)
    for name in ("export.gpkg", "faces.gpkg", "render.png"):
        if os.path.exists(o(name)):
            os.remove(o(name))
    return [
        ("faces", [t.shapes, "faces", packed]),
        ("shapes.all", [t.shapes, "all", packed]),
        ("shapes.largest", [t.shapes, "feature", packed, str(largest), "3"]),
        ("export", [t.inspect, "--force", "--export", o("export.gpkg"), packed]),
        ("export-faces", [t.inspect, "--force", "--export-faces", o("faces.gpkg"), packed]),
        ("verify", [t.inspect, "--verify", packed]),
        ("render", [t.inspect, "--force", "--render", o("render.png"), packed]),
        ("locate-batch", [t.locate, "locate", packed, points, "lonlat" if lonlat else "xy", "1"]),
    ]


def pack_cmd(t, src, key, packed):
    return [t.pack, "--force", "--json"] + (["--key", key] if key else []) + [src, "-o", packed]


def largest_feature(t, packed):
    return json.loads(timed([t.shapes, "all", packed])[0])["largest"]


def measure_full(t, data, label, src, key):
    """{stage: (wall, CPU, peak MiB or None)} and the map's counts for one
    map. The pack's stages share its process: their peak is the pack's."""
    packed = os.path.join(data, label + ".hpfc")
    out, whole = timed(pack_cmd(t, src, key, packed))
    rep = json.loads(out)
    cpu = rep["cpu_seconds"]
    wall = {"gis_read": rep["gis_seconds"]["read"], "gis_project": rep["gis_seconds"]["project"],
            "gis_node": rep["gis_seconds"]["node"], "gis_graph": rep["gis_seconds"]["graph"],
            "build": rep["build_seconds"], "write": rep["write_seconds"],
            "features": rep["features_seconds"]}
    for k in ("faces", "witness", "topology", "check"):
        wall["link_" + k] = rep["linking"][k + "_seconds"]
    r = {"pack": whole}
    for stage, field in PACK_REPORT.items():
        r[stage] = (wall[field], cpu[field], None)
    r["pack.write"] = (wall["write"] - wall["features"], cpu["write"] - cpu["features"], None)
    lonlat = rep["projection"] != "none"
    pts = points_file(data, label, src, rep["points_read"])
    for stage, cmd in commands(t, packed, data, largest_feature(t, packed), pts, lonlat):
        out, whole = timed(cmd)
        j = json.loads(out) if stage in IN_PROCESS else None
        if stage == "locate-batch":
            r[stage] = (j["locate_best_s"], j["locate_best_cpu_s"], whole[2])
        elif j:
            r[stage] = (j["wall_s"], j["cpu_s"], whole[2])
            if stage == "shapes.all":
                r["shapes.create"] = (j["create_wall_s"], j["create_cpu_s"], whole[2])
        else:
            r[stage] = whole
        print("  %-18s %-14s %8.3f s CPU %8.3f s wall %7.0f MiB" % (label, stage, r[stage][1],
              r[stage][0], r[stage][2]), file=sys.stderr, flush=True)
    counts = {k: rep[k] for k in ("points_read", "features_recorded", "faces", "edges",
                                  "file_bytes")}
    return counts, r


def callgrind_calls(path):
    """{(caller, callee): inclusive instructions} of a callgrind profile,
    the names without callgrind's recursion suffix ('2) and gcc's clones'
    (.constprop.0, ...)."""
    names = {}
    calls = {}
    fn = cfn = None
    pending = False

    def name(v):
        v = v.strip()
        if v.startswith("("):
            i = v.index(")")
            ident, rest = v[:i + 1], v[i + 1:].strip()
            if rest:
                names[ident] = rest
            v = names[ident]
        return re.sub(r"(\.(constprop|isra|part|cold)\.\d+)+$", "", v.split("'")[0])

    for line in open(path):
        if line.startswith("fn="):
            fn = name(line[3:])
        elif line.startswith("cfn="):
            cfn = name(line[4:])
        elif line.startswith("calls="):
            pending = True
        elif pending and (line[:1].isdigit() or line[:1] in "+-*"):
            cost = int(line.split()[1])
            calls[(fn, cfn)] = calls.get((fn, cfn), 0) + cost
            pending = False
    return calls


def instructions(calls, pairs):
    total = 0
    for pair in pairs:
        caller, callee, optional = pair[0], pair[1], len(pair) > 2
        found = [c for (a, b), c in calls.items() if b == callee and (caller is None or a == caller)]
        if not found and not optional:
            sys.exit("smoke: no call %s -> %s in the profile: the stage's functions have "
                     "changed; update PACK/CALLS in bench/scaling.py" % (caller or "*", callee))
        total += sum(found)
    return total


def measure_smoke(t, data, label, src, key):
    """{stage: instructions} and n for one map, every run under callgrind."""
    packed = os.path.join(data, label + ".hpfc")
    prof = os.path.join(data, "callgrind.out")

    def profile(cmd):
        if os.path.exists(prof):
            os.remove(prof)
        out, _ = timed(cmd, ["valgrind", "--tool=callgrind", "--callgrind-out-file=" + prof,
                              "--compress-strings=yes", "--compress-pos=no"])
        return out, callgrind_calls(prof)

    out, calls = profile(pack_cmd(t, src, key, packed))
    rep = json.loads(out)
    n = rep["points_read"]
    r = {stage: instructions(calls, pairs) for stage, pairs in PACK}
    lonlat = rep["projection"] != "none"
    pts = points_file(data, label, src, n)
    largest = largest_feature(t, packed)
    pairs = dict(CALLS)
    for stage, cmd in commands(t, packed, data, largest, pts, lonlat):
        out, calls = profile(cmd)
        r[stage] = instructions(calls, pairs[stage])
        if stage == "shapes.all":
            r["shapes.create"] = instructions(calls, pairs["shapes.create"])
    return n, r


# ---- exponents and tables ----------------------------------------------------


def exponent(n1, n2, t1, t2):
    if t1 <= 0 or t2 <= 0:
        return None
    return math.log(t2 / t1) / math.log(n2 / n1)


def fmt_e(e):
    if e is None:
        return "-"
    return ("**%.2f** !" if e > FLAG else "%.2f") % e


def table_full(name, labels, ns, rows):
    """Markdown: CPU seconds and peak MiB a size, CPU exponents between
    consecutive sizes, the wall and peak exponents of the last step."""
    head = ["stage"] + ["CPU s, %s (%s pts)" % (l, f"{n:,}") for l, n in zip(labels, ns)]
    head += ["peak MiB"] + ["exp CPU %d-%d" % (k + 1, k + 2) for k in range(len(ns) - 1)]
    head += ["exp wall %d-%d" % (len(ns) - 1, len(ns)), "exp peak %d-%d" % (len(ns) - 1, len(ns))]
    lines = ["%s:" % name, "", "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    exps = {}
    for stage in rows[0]:
        v = [r[stage] for r in rows]
        ec = [exponent(ns[k], ns[k + 1], v[k][1], v[k + 1][1]) for k in range(len(ns) - 1)]
        ew = exponent(ns[-2], ns[-1], v[-2][0], v[-1][0])
        ep = exponent(ns[-2], ns[-1], v[-2][2], v[-1][2]) if v[-1][2] else None
        exps[stage] = {"cpu": ec, "wall": ew, "peak": ep}
        peaks = " / ".join("%.0f" % x[2] for x in v) if v[-1][2] else "(pack's)"
        cells = [stage] + ["%.3f" % x[1] for x in v] + [peaks]
        cells += [fmt_e(e) for e in ec] + [fmt_e(ew), fmt_e(ep)]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines), exps


def peer_export(t, data, label, src, runs=3):
    """hpfc-inspect --export against ogr2ogr -f GPKG from the FlatGeobuf,
    interleaved; medians."""
    packed = os.path.join(data, label + ".hpfc")
    res = {"hpfc": [], "ogr2ogr": []}
    for _ in range(runs):
        for tool, out in (("hpfc", "peer-hpfc.gpkg"), ("ogr2ogr", "peer-ogr.gpkg")):
            out = os.path.join(data, out)
            if os.path.exists(out):
                os.remove(out)
            cmd = ([t.inspect, "--export", out, packed] if tool == "hpfc" else
                   ["ogr2ogr", "-f", "GPKG", out, src])
            res[tool].append(timed(cmd)[1])
    med = {k: [statistics.median(x[i] for x in v) for i in range(3)] for k, v in res.items()}
    return {"layer": label, "runs": runs, "hpfc": med["hpfc"], "ogr2ogr": med["ogr2ogr"],
            "ratio_wall": med["hpfc"][0] / med["ogr2ogr"][0],
            "ratio_cpu": med["hpfc"][1] / med["ogr2ogr"][1]}


def full(t, data, record):
    results = {"series": {}}
    for name, key, sizes in FULL:
        labels, ns, maps, rows = [], [], [], []
        for label, how in sizes:
            src = make_source(data, label, how)
            counts, r = measure_full(t, data, label, src, KEYS.get(label, key))
            labels.append(label)
            ns.append(counts["points_read"])
            maps.append(counts)
            rows.append(r)
        text, exps = table_full(name, labels, ns, rows)
        print(text + "\n", flush=True)
        results["series"][name] = {"labels": labels, "points": ns, "maps": maps, "rows": rows,
                                   "exponents": exps}
    label = PUBLIC[2][-1][0]
    p = peer_export(t, data, label, os.path.join(data, label + ".fgb"))
    results["peer_export"] = p
    print("export of %s: hpfc-inspect --export %.2f s CPU, %.2f s wall, %.0f MiB; ogr2ogr -f GPKG "
          "from FlatGeobuf %.2f s CPU, %.2f s wall, %.0f MiB: %.2fx CPU, %.2fx wall" % (
              label, p["hpfc"][1], p["hpfc"][0], p["hpfc"][2], p["ogr2ogr"][1], p["ogr2ogr"][0],
              p["ogr2ogr"][2], p["ratio_cpu"], p["ratio_wall"]))
    with open(os.path.join(data, "results-full.json"), "w") as f:
        json.dump(results, f, indent=1)
    if record:
        rec = load_record()
        rec["full"] = {s: {"points": v["points"],
                           "cpu": {k: [round(e, 3) if e is not None else None for e in x["cpu"]]
                                   for k, x in v["exponents"].items()}}
                       for s, v in results["series"].items()}
        save_record(rec)


def load_record():
    if os.path.exists(RECORD):
        with open(RECORD) as f:
            return json.load(f)
    return {}


def save_record(rec):
    with open(RECORD, "w") as f:
        json.dump(rec, f, indent=1, sort_keys=True)
        f.write("\n")


def smoke(t, data, record):
    name, key, sizes = SMOKE[0]
    ns, rows = [], []
    for label, how in sizes:
        src = make_source(data, label, how)
        n, r = measure_smoke(t, data, label, src, key)
        ns.append(n)
        rows.append(r)
    exps = {s: round(exponent(ns[0], ns[1], rows[0][s], rows[1][s]), 3) for s in rows[0]}
    rec = load_record()
    ref = rec.get("smoke", {})
    margin = ref.get("margin", 0.1)
    print("smoke: %s, %d -> %d shape points, instructions (callgrind)" % (name, ns[0], ns[1]))
    print("%-20s %14s %14s %9s %9s" % ("stage", "Ir small", "Ir large", "exponent", "recorded"))
    failed = []
    for s, e in exps.items():
        was = ref.get("exponents", {}).get(s)
        print("%-20s %14d %14d %9.3f %9s" % (s, rows[0][s], rows[1][s], e,
                                             "-" if was is None else "%.3f" % was))
        if was is not None and e > was + margin:
            failed.append("%s: exponent %.3f, recorded %.3f: grew by %.3f (margin %.2f)"
                          % (s, e, was, e - was, margin))
    if record:
        rec["smoke"] = {"series": name, "sizes": [l for l, _ in sizes], "points": ns,
                        "margin": margin, "exponents": exps}
        save_record(rec)
        print("recorded in %s" % RECORD)
        return 0
    failed += ["%s: no recorded exponent (sh bench/run-scaling.sh smoke --record)" % s
               for s in exps if s not in ref.get("exponents", {})]
    for f in failed:
        print("smoke: FAILED %s" % f)
    print("smoke: %s" % ("FAILED" if failed else "ok, every exponent within %.2f of its record"
                                                   % margin))
    return 1 if failed else 0


def main():
    if len(sys.argv) < 4 or sys.argv[1] not in ("full", "smoke"):
        sys.exit(__doc__)
    t = Tools(sys.argv[2])
    data = sys.argv[3]
    record = "--record" in sys.argv[4:]
    os.makedirs(data, exist_ok=True)
    if sys.argv[1] == "full":
        full(t, data, record)
        return 0
    return smoke(t, data, record)


if __name__ == "__main__":
    sys.exit(main())
