"""Independent counts for GeoJSON line/polygon fixtures (tests/cli/gis_*.sh).

    gis_oracle.py FILE.geojson...  prints {"all": {...}, "junctions": {...}}

Several files are one planar graph, as hpfc-pack merges several layers.

The oracle shares no code with hpfc-pack and uses neither GDAL nor GEOS: it
reads the GeoJSON with Python's json module, takes every line and ring as
straight segments in the file's own coordinates, and computes their exact
arrangement with rational arithmetic: every coordinate (a double, so a dyadic
rational) times one common power of two is an integer, and crossings are
fractions of those (Python ints are far faster than fractions for the bulk
of the comparisons). Distinct points, proper
crossings and touchings become vertices, each segment is split at every
vertex on it, and identical pieces count once. Then

    all:        vertices = points, edges = pieces
    junctions:  vertices = points of degree != 2 or where a line starts or
                stops, plus one per component
                without such a point (a closed ring); edges = vertices - points
                + pieces (each dropped degree-2 point joins two pieces)
    faces     = edges - vertices + components + 1 (Euler, with the outer face)

hpfc-pack projects and snaps to a lattice before noding; for data whose
features are much farther apart than the lattice unit, as in the fixtures,
neither changes the arrangement's topology, so the counts must agree.

Longitude/latitude files (no "crs" member, or CRS84 / EPSG:4326) are cut at
the antimeridian first, as hpfc-pack --wrap-dateline yes does (dateline.h),
but on linework only: a segment whose longitudes are more than 180 apart
(neither end a pole) becomes two, to (+-180, lat) on each side, lat exact;
each polygon adds, on both meridians, the latitude intervals inside it (its
crossings sorted, parity starting inside at -90 when it holds the south
pole), and the pole line it holds. A ring crossing an odd number of times
holds the pole of the hemisphere all its points are in.
"""
import json
import sys
from fractions import Fraction as Q

S = 1  # every coordinate times S is an integer (set by main)


def geographic(data):
    crs = ((data.get("crs") or {}).get("properties") or {}).get("name", "")
    return crs == "" or crs.endswith(("CRS84", "EPSG::4326", "EPSG:4326"))


def wraps(p, q):
    return abs(p[0] - q[0]) > 180 * S and abs(p[1]) != 90 * S and abs(q[1]) != 90 * S


def side(p):
    return 180 * S if p[0] > 0 else -180 * S


def crossing(p, q):
    e, w = (p, q) if p[0] > 0 else (q, p)
    de, dw = 180 * S - e[0], w[0] + 180 * S
    return e[1] if de == 0 else w[1] if dw == 0 else e[1] + (w[1] - e[1]) * Q(de, de + dw)


def cut_path(pts, lats):
    """The segments of a path, each wrapping one split at the meridian;
    appends the crossing latitudes to lats."""
    out = []
    for p, q in zip(pts, pts[1:]):
        if wraps(p, q):
            c = crossing(p, q)
            lats.append(c)
            out += [(p, (side(p), c)), ((side(q), c), q)]
        else:
            out.append((p, q))
    return out


def cut_polygon(rings):
    """The linework of a polygon (its rings, closed) cut at the meridian."""
    out, lats, south, poles = [], [], False, set()
    for ring in rings:
        n = len(lats)
        out += cut_path(ring, lats)
        if (len(lats) - n) % 2:  # winds around the pole of its hemisphere
            ys = [p[1] for p in ring]
            if max(ys) > 0 and min(ys) < 0 or min(ys) == max(ys) == 0:
                sys.exit("gis_oracle: a ring winding around a pole crosses the equator")
            poles.add(max(ys) <= 0)
            south ^= max(ys) <= 0
    if len(poles) > 1:
        sys.exit("gis_oracle: rings winding around both poles")
    if not lats:
        return out
    e, w, pole = 180 * S, -180 * S, 90 * S
    inside, prev = south, -pole
    for lat in sorted(lats) + [pole]:
        if inside and lat > prev:
            out += [((x, prev), (x, lat)) for x in (e, w)]
        inside, prev = not inside, lat
    if south:
        out.append(((e, -pole), (w, -pole)))
    if not inside:  # toggled once past +90: inside there
        out.append(((e, pole), (w, pole)))
    return out


def polygons(geom):
    """Each polygon (list of rings) and each line (a one-ring list, open)."""
    t = geom["type"] if geom else None
    c = geom.get("coordinates") if geom else None
    if t == "Polygon":
        yield c, True
    elif t == "MultiPolygon":
        for poly in c:
            yield poly, True
    elif t == "LineString":
        yield [c], False
    elif t == "MultiLineString":
        for line in c:
            yield [line], False
    elif t == "GeometryCollection":
        for g in geom["geometries"]:
            yield from polygons(g)


def segments(geom, cut, ends=None):
    """The segments of a geometry; with `ends`, the points where its lines
    (open parts, after the meridian cut) start and stop are added to it."""
    for rings, closed in polygons(geom):
        if ends is not None and not closed:
            for r in rings:
                if not r:
                    continue
                r = [(exact(x), exact(y)) for x, y, *_ in r]
                run = [s for s in (cut_path(r, []) if cut else zip(r, r[1:])) if s[0] != s[1]]
                for i, (a, b) in enumerate(run):
                    if i == 0 or run[i - 1][1] != a:
                        ends.add(a)
                    if i + 1 == len(run) or run[i + 1][0] != b:
                        ends.add(b)
        rings = [[(exact(x), exact(y)) for x, y, *_ in r] for r in rings if r]
        if closed:
            rings = [r + [r[0]] if r[0] != r[-1] else r for r in rings]
        if cut and closed:
            yield from cut_polygon(rings)
        elif cut:
            for r in rings:
                yield from cut_path(r, [])
        else:
            for r in rings:
                yield from zip(r, r[1:])


def exact(v):
    n, d = v.as_integer_ratio()
    return n * (S // d)


def scale(datas):
    """The least power of two that makes every coordinate an integer."""
    bits = 0

    def walk(c):
        nonlocal bits
        if isinstance(c, (int, float)):
            bits = max(bits, c.as_integer_ratio()[1].bit_length() - 1)
        elif isinstance(c, list):
            for x in c:
                walk(x)
        elif isinstance(c, dict):
            walk(c.get("coordinates"))
            walk(c.get("geometries"))
            walk(c.get("geometry"))
            walk(c.get("features"))

    for d in datas:
        walk(d)
    return 1 << bits


def cross(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def on_segment(p, a, b):
    return (cross(a, b, p) == 0 and min(a[0], b[0]) <= p[0] <= max(a[0], b[0])
            and min(a[1], b[1]) <= p[1] <= max(a[1], b[1]))


def intersections(a, b, c, d):
    """Points shared by closed segments ab and cd (endpoints of overlaps)."""
    d1, d2 = cross(c, d, a), cross(c, d, b)
    d3, d4 = cross(a, b, c), cross(a, b, d)
    if d1 == d2 == 0:  # collinear: the shared endpoints, if any
        return [p for p in (a, b) if on_segment(p, c, d)] + \
               [p for p in (c, d) if on_segment(p, a, b)]
    if (d1 > 0 and d2 > 0) or (d1 < 0 and d2 < 0) or (d3 > 0 and d4 > 0) or (d3 < 0 and d4 < 0):
        return []
    t = Q(d1, d1 - d2)
    return [(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))]


def main():
    global S
    datas = [json.load(open(path)) for path in sys.argv[1:]]
    S = scale(datas)
    segs = set()
    ends = set()  # where lines start and stop: vertices whatever their degree
    for data in datas:
        feats = data["features"] if data.get("type") == "FeatureCollection" else [data]
        cut = geographic(data)
        for f in feats:
            for p, q in segments(f.get("geometry"), cut, ends):
                if p != q:
                    segs.add((min(p, q), max(p, q)))
    segs = sorted(segs)
    on = {s: {s[0], s[1]} for s in segs}
    # sweep on x: pairs whose x ranges overlap
    for i, s in enumerate(segs):
        for k in range(i + 1, len(segs)):  # no slice: a copy per segment is quadratic
            t = segs[k]
            if t[0][0] > s[1][0]:
                break
            if max(s[0][1], s[1][1]) < min(t[0][1], t[1][1]) or \
               max(t[0][1], t[1][1]) < min(s[0][1], s[1][1]):
                continue
            for p in intersections(s[0], s[1], t[0], t[1]):
                on[s].add(p)
                on[t].add(p)
    pieces = set()
    for s in segs:
        pts = sorted(on[s])
        for p, q in zip(pts, pts[1:]):
            pieces.add((p, q))
    adj = {}
    for p, q in pieces:
        adj.setdefault(p, []).append(q)
        adj.setdefault(q, []).append(p)
    parent = {p: p for p in adj}

    def find(p):
        while parent[p] != p:
            parent[p] = parent[parent[p]]
            p = parent[p]
        return p

    for p, q in pieces:
        parent[find(p)] = find(q)
    comps = len({find(p) for p in adj})
    nv, ne = len(adj), len(pieces)
    faces = ne - nv + comps + 1
    # junctions: each degree-2 point merges two edges into one, unless a
    # line ends there; a closed chain of degree-2 points keeps one vertex
    # and one edge
    junc = [p for p in adj if len(adj[p]) != 2 or p in ends]
    cycles = comps - len({find(p) for p in junc})
    njv = len(junc) + cycles
    nje = ne - (nv - njv)
    print(json.dumps({
        "all": {"vertices": nv, "edges": ne, "faces": faces, "components": comps},
        "junctions": {"vertices": njv, "edges": nje, "faces": faces, "components": comps},
    }))


main()
