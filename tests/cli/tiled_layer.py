#!/usr/bin/env python3
"""Tiled layers, as quadtree tiling tools write them, and their oracle, for
tests/cli/gis_tiled.sh (and bench/run-geotz.sh's check).

    tiled_layer.py make SOURCE OUT.geojson SEED UNIT DEPTH VARIANT
        Cuts the polygon layer SOURCE into quadtree cells of its box, down
        to DEPTH levels: a cell wholly inside one feature becomes that
        cell's rectangle (a feature of its own, with the source feature's
        properties), a cell on a border is cut again, and at DEPTH each
        feature's piece in the cell is its own feature. Rectangles are cut
        on one root box, pieces on another whose sides differ by 0 to 10
        UNITs (the lattice unit the pack will choose), as tiling tools that
        round their cell bounds differently do:
          exact    the same box
          overlap  the pieces' box larger: pieces overlap the rectangles
          sliver   the pieces' box smaller: slivers between them
          mixed    each side moved either way
        and with VARIANT+dup, one feature in 20 written twice.
    tiled_layer.py check SOURCE EXPORT POINTS_OUT BAND SEED
        SOURCE: the tiled layer; EXPORT: hpfc-inspect --export of its pack
        (same feature order). Fails unless every exported feature equals
        its source polygon up to a band BAND wide along the source's border
        (no part of their symmetric difference lies farther than BAND from
        the border), and writes POINTS_OUT: random points more than 2 BAND
        inside the source polygons, "x,y,fid" lines.
    tiled_layer.py located LOCATE_BATCH_OUT POINTS
        Fails unless every point's answer (hpfc-inspect --locate-batch,
        JSON lines) names the feature the point was drawn in.

Coordinates stay those of SOURCE, packed with --projection none, so UNIT
and BAND are in SOURCE's units.
"""
import json
import random
import sys

from shapely.geometry import Polygon, box, mapping, shape
from shapely.ops import unary_union
from shapely.validation import make_valid

VARIANTS = ("exact", "overlap", "sliver", "mixed")


def polygonal(g):
    """The areal part of g (make_valid can leave lines and points)."""
    if g.is_empty:
        return g
    if g.geom_type in ("Polygon", "MultiPolygon"):
        return g
    if g.geom_type == "GeometryCollection":
        return unary_union([p for p in g.geoms if p.geom_type in ("Polygon", "MultiPolygon")])
    return Polygon()


def load(path):
    data = json.load(open(path))
    feats = []
    for f in data["features"]:
        g = f.get("geometry")
        if not g or g["type"] not in ("Polygon", "MultiPolygon"):
            continue
        feats.append((polygonal(make_valid(shape(g))), f.get("properties") or {}))
    return feats


def cell_box(root, depth, i, j):
    x0, y0, x1, y1 = root
    n = 1 << depth
    w, h = (x1 - x0) / n, (y1 - y0) / n
    return (x0 + i * w, y0 + j * h, x0 + (i + 1) * w, y0 + (j + 1) * h)


def make(src, out, seed, unit, depth, variant):
    rng = random.Random(seed)
    dup = variant.endswith("+dup")
    variant = variant.replace("+dup", "")
    if variant not in VARIANTS:
        sys.exit(f"tiled_layer.py: unknown variant {variant}")
    feats = [(g, p) for g, p in load(src) if not g.is_empty]
    xs = [g.bounds for g, _ in feats]
    root = (min(b[0] for b in xs), min(b[1] for b in xs),
            max(b[2] for b in xs), max(b[3] for b in xs))

    def moved(sign):
        return rng.randint(0, 10) * unit * sign

    sides = {"exact": (0, 0, 0, 0),
             "overlap": (-moved(1), -moved(1), moved(1), moved(1)),
             "sliver": (moved(1), moved(1), -moved(1), -moved(1)),
             "mixed": tuple(moved(rng.choice((-1, 1))) for _ in range(4))}[variant]
    root2 = tuple(r + d for r, d in zip(root, sides))
    out_feats = []

    def emit(geom, props):
        for _ in range(2 if dup and rng.random() < 0.05 else 1):
            out_feats.append({"type": "Feature", "properties": props, "geometry": mapping(geom)})

    def visit(d, i, j, candidates):
        b = box(*cell_box(root, d, i, j))
        inside = [k for k in candidates if feats[k][0].intersects(b)]
        if not inside:
            return
        whole = [k for k in inside if feats[k][0].contains(b)]
        if len(whole) == 1 and len(inside) == 1:
            emit(b, feats[whole[0]][1])
            return
        if d == depth:
            b2 = box(*cell_box(root2, d, i, j))
            for k in inside:
                piece = polygonal(feats[k][0].intersection(b2))
                if not piece.is_empty and piece.area > 0:
                    emit(piece, feats[k][1])
            return
        for di in (0, 1):
            for dj in (0, 1):
                visit(d + 1, 2 * i + di, 2 * j + dj, inside)

    visit(0, 0, 0, list(range(len(feats))))
    json.dump({"type": "FeatureCollection", "features": out_feats}, open(out, "w"))
    print(f"{len(out_feats)} features ({variant}{' +dup' if dup else ''}, root boxes differ by "
          f"{[round(s / unit) for s in sides]} units)")


def check(src, export, points_out, band, seed):
    rng = random.Random(seed)
    source = [g for g, _ in load(src)]
    got = json.load(open(export))["features"]
    if len(got) != len(source):
        sys.exit(f"{len(got)} features exported, {len(source)} in the source")
    worst, bad, pts = 0.0, [], []
    for k, (s, f) in enumerate(zip(source, got)):
        g = shape(f["geometry"]) if f.get("geometry") else None
        g = g if g is not None else Polygon()
        diff = s.symmetric_difference(g)
        outside = diff.difference(s.boundary.buffer(band, 4)) if not diff.is_empty else diff
        # what is left beyond the band: buffering rounds corners, so allow
        # a corner's worth of area per vertex
        slack = band * band * (len(s.boundary.coords) if s.boundary.geom_type == "LineString"
                               else sum(len(r.coords) for r in s.boundary.geoms))
        if outside.area > slack:
            bad.append((k, outside.area, s.area))
        worst = max(worst, outside.area)
        core = s.buffer(-2 * band)
        if core.is_empty:
            continue
        x0, y0, x1, y1 = core.bounds
        for _ in range(3):
            for _ in range(50):
                x, y = rng.uniform(x0, x1), rng.uniform(y0, y1)
                if core.contains(shape({"type": "Point", "coordinates": (x, y)})):
                    pts.append((x, y, k))
                    break
    if bad:
        for k, area, whole in bad[:10]:
            print(f"feature {k}: {area:.6g} of its {whole:.6g} lies outside the band",
                  file=sys.stderr)
        sys.exit(f"{len(bad)} of {len(source)} features differ from their source beyond the band")
    with open(points_out, "w") as f:
        for x, y, k in pts:
            f.write(f"{x!r},{y!r},{k}\n")
    print(f"{len(source)} features within the band (largest area outside it {worst:.3g}); "
          f"{len(pts)} points drawn")


def located(answers_path, points_path):
    want = [int(line.rsplit(",", 1)[1]) for line in open(points_path) if line.strip()]
    answers = [json.loads(line) for line in open(answers_path)]
    if len(answers) != len(want):
        sys.exit(f"{len(answers)} answers for {len(want)} points")
    wrong = [(k, a, w) for k, (a, w) in enumerate(zip(answers, want))
             if w not in [f["fid"] for f in a.get("features", [])]]
    for k, a, w in wrong[:10]:
        print(f"point {k} ({a.get('x')}, {a.get('y')}): fid {w} not among "
              f"{[f['fid'] for f in a.get('features', [])]}", file=sys.stderr)
    if wrong:
        sys.exit(f"{len(wrong)} of {len(want)} points do not locate to their feature")
    print(f"{len(want)} points locate to their feature")


if __name__ == "__main__":
    cmd = sys.argv[1] if len(sys.argv) > 1 else ""
    if cmd == "make" and len(sys.argv) == 8:
        make(sys.argv[2], sys.argv[3], int(sys.argv[4]), float(sys.argv[5]), int(sys.argv[6]),
             sys.argv[7])
    elif cmd == "check" and len(sys.argv) == 7:
        check(sys.argv[2], sys.argv[3], sys.argv[4], float(sys.argv[5]), int(sys.argv[6]))
    elif cmd == "located" and len(sys.argv) == 4:
        located(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)
