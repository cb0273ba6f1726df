"""Independent counts for a GeoJSON line/polygon fixture (tests/cli/gis_*.sh).

    gis_oracle.py FILE.geojson     prints {"all": {...}, "junctions": {...}}

The oracle shares no code with hpfc-pack and uses neither GDAL nor GEOS: it
reads the GeoJSON with Python's json module, takes every line and ring as
straight segments in the file's own coordinates, and computes their exact
arrangement with rational arithmetic (fractions): distinct points, proper
crossings and touchings become vertices, each segment is split at every
vertex on it, and identical pieces count once. Then

    all:        vertices = points, edges = pieces
    junctions:  vertices = points of degree != 2, plus one per component
                without such a point (a closed ring); edges = vertices - points
                + pieces (each dropped degree-2 point joins two pieces)
    faces     = edges - vertices + components + 1 (Euler, with the outer face)

hpfc-pack projects and snaps to a lattice before noding; for data whose
features are much farther apart than the lattice unit, as in the fixtures,
neither changes the arrangement's topology, so the counts must agree.
"""
import json
import sys
from fractions import Fraction as Q


def parts(geom):
    t = geom["type"] if geom else None
    c = geom.get("coordinates") if geom else None
    if t == "LineString":
        yield c
    elif t == "MultiLineString" or t == "Polygon":
        yield from c
    elif t == "MultiPolygon":
        for poly in c:
            yield from poly
    elif t == "GeometryCollection":
        for g in geom["geometries"]:
            yield from parts(g)


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
    t = d1 / (d1 - d2)
    return [(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))]


def main():
    data = json.load(open(sys.argv[1]))
    feats = data["features"] if data.get("type") == "FeatureCollection" else [data]
    segs = set()
    for f in feats:
        for line in parts(f.get("geometry")):
            pts = [(Q(x), Q(y)) for x, y, *_ in line]
            for p, q in zip(pts, pts[1:]):
                if p != q:
                    segs.add((min(p, q), max(p, q)))
    segs = sorted(segs)
    on = {s: {s[0], s[1]} for s in segs}
    # sweep on x: pairs whose x ranges overlap
    for i, s in enumerate(segs):
        for t in segs[i + 1:]:
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
    # junctions: each degree-2 point merges two edges into one; a closed
    # chain of degree-2 points keeps one vertex and one edge
    junc = [p for p in adj if len(adj[p]) != 2]
    cycles = comps - len({find(p) for p in junc})
    njv = len(junc) + cycles
    nje = ne - (nv - njv)
    print(json.dumps({
        "all": {"vertices": nv, "edges": ne, "faces": faces, "components": comps},
        "junctions": {"vertices": njv, "edges": nje, "faces": faces, "components": comps},
    }))


main()
