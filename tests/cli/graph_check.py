"""Checks of hpfc-inspect --verify and --export-graph (tests/cli/verify.sh,
tests/cli/export_graph.sh).

    graph_check.py verified VERIFY.json PFC REPORT.json
        --verify --json says valid, with the .pfc's vertex and edge counts and
        the faces and components of hpfc-pack's --json build report
    graph_check.py invalid VERIFY.json
        --verify --json says invalid, with at least one problem
    graph_check.py graph GRAPH.json [PFC [UNIT_EXP10]]
        GRAPH.json has the shape of interfaces §3 and is a planar map: twin an
        involution without fixed points, next a permutation, origin(next(d)) =
        origin(twin(d)), and V - E + (orbits of next) = 2C (genus 0). With
        PFC: as many vertices and edges, and a one-to-one matching of the .pfc
        vertices to exported vertices of the same degree whose box holds them,
        compared exactly as decimals; boxes are written with exactly
        -UNIT_EXP10 decimals (the input's units); and for graphs with only
        straight edges between distinct pairs, the loops of next go clockwise
        around bounded faces (negative area) and counter-clockwise around the
        outside, one per component.
    graph_check.py counts GRAPH.json VERIFY.json
        the graph has the vertices and edges --verify counted
    graph_check.py flip IN PREFIX COUNT [fix]
        PREFIX0.hpfc .. PREFIX<COUNT-1>.hpfc: IN with one bit of its POOL
        section flipped (bit k chosen by random seed k); with "fix", the POOL
        and header checksums are recomputed so that the flip reaches the
        structural checks
    graph_check.py flip IN PREFIX COUNT fix TAG
        the same in section TAG (e.g. LABL) instead of POOL
    graph_check.py alias IN OUT
        OUT = IN with every refined pixel of a level pointing at one image of
        the next level, the one with the most refined pixels (checksums
        recomputed): a small file whose tree paths multiply level by level

Exit status 0 when the check holds, 1 with a one-line reason otherwise.
"""
import json
import random
import re
import struct
import sys
from decimal import Decimal


def fail(msg):
    print("graph_check.py: " + msg, file=sys.stderr)
    sys.exit(1)


def load(path, **kw):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f, **kw)
    except (OSError, ValueError) as e:
        fail(f"{path}: not valid JSON: {e}")


# ---- .pfc input -----------------------------------------------------------

def read_pfc(path):
    """Vertices (exact Decimals) and edges (u, v, interior point count)."""
    verts, edges = [], []
    with open(path, "rb") as f:
        for line in f:
            fields = line.split(b"#", 1)[0].decode().split()
            if fields and fields[0] == "v":
                verts.append((Decimal(fields[1]), Decimal(fields[2])))
            elif fields and fields[0] == "e":
                edges.append((int(fields[1]), int(fields[2]), (len(fields) - 3) // 2))
    return verts, edges


def degrees(nv, pairs):
    deg = [0] * nv
    for u, v in pairs:
        deg[u] += 1
        deg[v] += 1
    return deg


# ---- --verify reports -------------------------------------------------------

def verified(path, pfc, report_path):
    r, b = load(path), load(report_path)
    verts, edges = read_pfc(pfc)
    if r.get("valid") is not True or r.get("problem_count") != 0 or r.get("problems") != []:
        fail(f"{path}: not valid: {r.get('problems')}")
    if any(v != "ok" for v in r["checks"].values()):
        fail(f"{path}: a check is not ok: {r['checks']}")
    got = (r["vertices"], r["edges"], r["faces"], r["components"])
    want = (len(verts), len(edges), b["faces"], b["components"])
    if got != want:
        fail(f"{path}: V, E, F, C = {got}; the input and hpfc-pack say {want}")
    if r["boundary_loops"] != r["faces"] + r["components"] - 1:
        fail(f"{path}: boundary loops != F + C - 1")
    if r["levels"] != b["level_count"] or r["pixels"] != b["total_pixels"]:
        fail(f"{path}: levels or pixels differ from hpfc-pack's report")
    if r["private_pixels"] != b["private_pixels"]:
        fail(f"{path}: private pixels differ from hpfc-pack's report")


def invalid(path):
    r = load(path)
    if r.get("valid") is not False or not r.get("problems") or r.get("problem_count", 0) < 1:
        fail(f"{path}: not reported invalid with a problem")


# ---- --export-graph ---------------------------------------------------------

NUMBER = re.compile(rb"-?(0|[1-9][0-9]*)(\.[0-9]+)?")


def box_texts(path):
    """The box numbers as written, to check their decimals."""
    data = open(path, "rb").read()
    for m in re.finditer(rb'"box"\s*:\s*\[([^\]]*)\]', data):
        yield [t.strip() for t in m.group(1).split(b",")]


def shape(g, path):
    if g.get("format") != "hpfc-graph" or g.get("version") != 1:
        fail(f"{path}: not format hpfc-graph version 1")
    vs, ds = g.get("vertices"), g.get("darts")
    if not isinstance(vs, list) or not isinstance(ds, list):
        fail(f"{path}: vertices or darts is not a list")
    for v in vs:
        b = v.get("box") if isinstance(v, dict) else None
        if not isinstance(b, list) or len(b) != 4 or not all(
                isinstance(x, (int, Decimal)) and not isinstance(x, bool) for x in b):
            fail(f"{path}: bad vertex {v}")
        b[:] = [Decimal(x) for x in b]
        if not (b[0] < b[2] and b[1] < b[3]):
            fail(f"{path}: empty box {b}")
    for d in ds:
        if not isinstance(d, dict) or any(
                not isinstance(d.get(k), int) or isinstance(d.get(k), bool) or
                not 0 <= d[k] < (len(vs) if k == "origin" else len(ds))
                for k in ("origin", "twin", "next")):
            fail(f"{path}: bad dart {d}")
    return vs, ds


def components(nv, ds):
    parent = list(range(nv))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a
    c = nv
    for d in ds:
        a, b = find(d["origin"]), find(ds[d["twin"]]["origin"])
        if a != b:
            parent[a] = b
            c -= 1
    return c


def loops_of(ds):
    seen, loops = [False] * len(ds), []
    for d in range(len(ds)):
        loop = []
        while not seen[d]:
            seen[d] = True
            loop.append(d)
            d = ds[d]["next"]
        if loop:
            loops.append(loop)
    return loops


def planar_map(vs, ds, path):
    if len(ds) % 2:
        fail(f"{path}: odd number of darts")
    for i, d in enumerate(ds):
        t = d["twin"]
        if t == i or ds[t]["twin"] != i:
            fail(f"{path}: dart {i}: twin is not an involution without fixed points")
        if ds[d["next"]]["origin"] != ds[t]["origin"]:
            fail(f"{path}: dart {i}: origin(next(d)) != origin(twin(d))")
    if sorted(d["next"] for d in ds) != list(range(len(ds))):
        fail(f"{path}: next is not a permutation")
    loops = loops_of(ds)
    c = components(len(vs), ds)
    if len(vs) - len(ds) // 2 + len(loops) != 2 * c:
        fail(f"{path}: V - E + loops = {len(vs) - len(ds) // 2 + len(loops)}, not 2C = {2 * c}")
    return loops, c


def box_index(vs):
    """Finds the exported vertices whose box holds a point: boxes are cells of
    one grid per size, so each size needs one lookup."""
    by_box, phase = {}, {}
    for i, v in enumerate(vs):
        b = tuple(v["box"])
        by_box.setdefault(b, []).append(i)
        phase.setdefault((b[2] - b[0], b[3] - b[1]), (b[0], b[1]))

    def holding(x, y):
        for (w, h), (bx, by) in phase.items():
            x0 = bx + ((x - bx) // w) * w
            y0 = by + ((y - by) // h) * h
            if x0 > x:
                x0 -= w
            if y0 > y:
                y0 -= h
            found = by_box.get((x0, y0, x0 + w, y0 + h))
            if found:
                return found
        return []
    return holding


def match(verts, deg_in, vs, deg_out, path):
    """A perfect matching of input vertices to exported ones of the same
    degree whose half-open box holds them (Kuhn's augmenting paths)."""
    holding = box_index(vs)
    cand = []
    for k, (x, y) in enumerate(verts):
        c = [i for i in holding(x, y) if deg_out[i] == deg_in[k]]
        for i in c:
            b = vs[i]["box"]
            if not (b[0] <= x < b[2] and b[1] <= y < b[3]):
                fail(f"{path}: internal: box lookup")
        if not c:
            fail(f"{path}: input vertex {k} ({x}, {y}), degree {deg_in[k]}: no exported vertex "
                 "of that degree has a box holding it")
        cand.append(c)
    owner = {}

    def augment(k, seen):
        for i in cand[k]:
            if i not in seen:
                seen.add(i)
                if i not in owner or augment(owner[i], seen):
                    owner[i] = k
                    return True
        return False
    sys.setrecursionlimit(max(1000, 4 * len(verts) + 100))
    for k in range(len(verts)):
        if not augment(k, set()):
            fail(f"{path}: input vertex {k} cannot be matched to its own exported vertex")
    # exported vertices that only one input vertex can match, and vice versa
    rivals = {}
    for c in cand:
        for i in c:
            rivals[i] = rivals.get(i, 0) + 1
    certain = {c[0] for c in cand if len(c) == 1 and rivals[c[0]] == 1}
    return owner, certain


def orientation(loops, ds, where, c, path):
    """Twice the signed area of each loop with straight edges: negative
    (clockwise) around a bounded face, positive around the outside of each
    component. `where` places the exported vertices whose input vertex is
    certain (alone in its box with its degree); loops through the others are
    skipped, so at most C loops may turn counter-clockwise."""
    positive = checked = 0
    for loop in loops:
        if any(ds[d]["origin"] not in where for d in loop):
            continue
        checked += 1
        pts = [where[ds[d]["origin"]] for d in loop]
        a = sum(p[0] * q[1] - q[0] * p[1] for p, q in zip(pts, pts[1:] + pts[:1]))
        if a == 0:
            fail(f"{path}: a boundary loop of zero area")
        positive += a > 0
    if positive > c or (checked == len(loops) and positive != c):
        fail(f"{path}: {positive} counter-clockwise loops, expected one per component ({c}): "
             "next must turn clockwise around bounded faces")


def graph(path, pfc=None, unit=None):
    g = load(path, parse_float=Decimal)
    vs, ds = shape(g, path)
    loops, c = planar_map(vs, ds, path)
    if unit is not None:
        frac = max(0, -int(unit))
        for nums in box_texts(path):
            for t in nums:
                m = NUMBER.fullmatch(t)
                decimals = len(m.group(2)) - 1 if m and m.group(2) else 0
                if not m or decimals != frac:
                    fail(f"{path}: box number {t!r} is not a decimal with {frac} decimals")
    if pfc is None:
        return
    verts, edges = read_pfc(pfc)
    if (len(vs), len(ds) // 2) != (len(verts), len(edges)):
        fail(f"{path}: {len(vs)} vertices, {len(ds) // 2} edges; {pfc} has "
             f"{len(verts)}, {len(edges)}")
    deg_in = degrees(len(verts), [(u, v) for u, v, _ in edges])
    deg_out = [0] * len(vs)
    for d in ds:
        deg_out[d["origin"]] += 1
    owner, certain = match(verts, deg_in, vs, deg_out, path)
    pairs = {(min(u, v), max(u, v)) for u, v, _ in edges}
    if all(n == 0 for _, _, n in edges) and len(pairs) == len(edges):
        orientation(loops, ds, {i: verts[k] for i, k in owner.items() if i in certain}, c, path)


def counts(path, verify_path):
    g, r = load(path), load(verify_path)
    if (len(g["vertices"]), len(g["darts"]) // 2) != (r["vertices"], r["edges"]):
        fail(f"{path}: the graph and --verify count different vertices or edges")


# ---- damaged files ----------------------------------------------------------

def crc32c(data):
    crc = 0xFFFFFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0x82F63B78 if crc & 1 else crc >> 1
    return crc ^ 0xFFFFFFFF


def flip_one(data, seed, fix, tag=b"POOL"):
    b = bytearray(data)
    header_size, = struct.unpack_from("<I", b, 12)
    levels, count = struct.unpack_from("<II", b, 40)
    meta_size, = struct.unpack_from("<Q", b, 96)
    for k in range(count):
        e = header_size + 64 * levels + 32 * k
        if b[e:e + 4] != tag:
            continue
        off, length = struct.unpack_from("<QQ", b, e + 8)
        bit = random.Random(seed).randrange(8 * length)
        b[off + bit // 8] ^= 0x80 >> (bit % 8)
        if fix:
            struct.pack_into("<I", b, e + 24, crc32c(b[off:off + length]))
            struct.pack_into("<I", b, 124, 0)
            struct.pack_into("<I", b, 124, crc32c(b[:meta_size]))
    return b


def flip(src, prefix, count, fix=None, tag="POOL"):
    data = open(src, "rb").read()
    for seed in range(int(count)):
        with open(f"{prefix}{seed}.hpfc", "wb") as f:
            f.write(flip_one(data, seed, fix, tag.encode()))


def get_bits(b, base, bit, k):
    v = 0
    for i in range(bit, bit + k):
        v = v << 1 | (b[base + i // 8] >> (7 - i % 8) & 1)
    return v


def set_bits(b, base, bit, k, value):
    for i in range(bit, bit + k):
        mask = 0x80 >> (i % 8)
        if value >> (bit + k - 1 - i) & 1:
            b[base + i // 8] |= mask
        else:
            b[base + i // 8] &= ~mask & 0xFF


def refined_slots(b, off, bits, l, lv, dims):
    """(address bit of each refined pixel of level l, in pool order;
    {image offset: its refined pixel count})."""
    n0, m0, n, m = dims
    kw, ka = lv[l][0], lv[l][1]
    slots, images = [], {}
    if l == 0:
        rec = 1 + max(kw, ka)
        slots = [r * rec + 1 for r in range(n0 * m0) if get_bits(b, off, r * rec, 1)]
        return slots, {0: len(slots)}
    a = 0
    while a < bits:
        slot, images[a] = a + n * m, 0
        for p in range(n * m):
            t = get_bits(b, off, a + p, 1)
            if t:
                slots.append(slot)
                images[a] += 1
            slot += ka if t else kw
        a = slot
    return slots, images


def alias(src, dst):
    """Points every refined pixel of each level at the next level's image
    with the most refined pixels, so the number of root-to-leaf paths
    multiplies level by level while the file keeps its size."""
    b = bytearray(open(src, "rb").read())
    header_size, = struct.unpack_from("<I", b, 12)
    dims = struct.unpack_from("<IIII", b, 24)
    levels, count = struct.unpack_from("<II", b, 40)
    meta_size, = struct.unpack_from("<Q", b, 96)
    lv = [struct.unpack_from("<IIQQ", b, header_size + 64 * l + 24) for l in range(levels)]
    found = [refined_slots(b, lv[l][2], lv[l][3], l, lv, dims) for l in range(levels)]
    for l in range(levels - 1):
        images = found[l + 1][1]
        target = max(images, key=lambda a: images[a]) if images else 0
        for slot in found[l][0]:
            set_bits(b, lv[l][2], slot, lv[l][1], target)
    for k in range(count):
        e = header_size + 64 * levels + 32 * k
        o, length = struct.unpack_from("<QQ", b, e + 8)
        struct.pack_into("<I", b, e + 24, crc32c(b[o:o + length]))
    struct.pack_into("<I", b, 124, 0)
    struct.pack_into("<I", b, 124, crc32c(b[:meta_size]))
    open(dst, "wb").write(b)


def main(argv):
    cmds = {"verified": (verified, 3, 3), "invalid": (invalid, 1, 1), "graph": (graph, 1, 3),
            "counts": (counts, 2, 2), "flip": (flip, 3, 5), "alias": (alias, 2, 2)}
    if len(argv) < 2 or argv[1] not in cmds:
        fail("usage: graph_check.py verified|invalid|graph|counts|flip|alias ARGS")
    fn, lo, hi = cmds[argv[1]]
    if not lo <= len(argv) - 2 <= hi:
        fail(f"{argv[1]}: wrong number of arguments")
    fn(*argv[2:])


if __name__ == "__main__":
    main(sys.argv)
