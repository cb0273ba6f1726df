#!/bin/sh
# hpfc-inspect --locate / --locate-batch on files with exact geometry (issue
# 16, interfaces §4; spec §6.7): one face per point, or on an edge or a
# vertex "on_boundary" with the faces around it and the edge or vertex id,
# "exact": true; a file packed --no-geometry keeps its candidate faces with
# "exact": false. The oracle is the input graph: a square ring around a
# square hole and a triangle (tests/data/valid/two_components_hole.pfc),
# whose faces are told apart by which points share one.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

in=$TESTS/data/valid/two_components_hole.pfc
"$PACK" --quiet "$in" -o "$tmp/hole.hpfc" || fail "cannot pack"
"$PACK" --quiet --no-geometry "$in" -o "$tmp/rough.hpfc" || fail "cannot pack --no-geometry"

points="2,2 10,10 25,10 35,3 0,0 10,0 5,10 15,15 35,8 20,7 1000,1000"
: >"$tmp/one.jsonl"
: >"$tmp/pts.csv"
for p in $points; do
    run "$INSPECT" --locate "$p" --json "$tmp/hole.hpfc"
    [ "$rc" -eq 0 ] || fail "--locate $p: exit $rc: $(cat "$tmp/err")"
    cat "$tmp/out" >>"$tmp/one.jsonl"
    echo "$p" >>"$tmp/pts.csv"
done
run "$INSPECT" --locate-batch "$tmp/pts.csv" "$tmp/hole.hpfc"
[ "$rc" -eq 0 ] || fail "--locate-batch: exit $rc"
cp "$tmp/out" "$tmp/batch.jsonl"
run "$INSPECT" --locate 2,2 --json "$tmp/rough.hpfc"
cp "$tmp/out" "$tmp/rough.json"

python3 - "$tmp/one.jsonl" "$tmp/batch.jsonl" "$tmp/rough.json" <<'PY' || fail "exact answers"
import json, sys
one = [json.loads(l) for l in open(sys.argv[1])]
batch = [json.loads(l) for l in open(sys.argv[2])]
rough = json.load(open(sys.argv[3]))
pts = ["2,2", "10,10", "25,10", "35,3", "0,0", "10,0", "5,10", "15,15", "35,8", "20,7", "1000,1000"]
a = dict(zip(pts, one))
for p, r in a.items():
    if p == "1000,1000":
        continue
    assert r["exact"] is True and r["inside"], (p, r)
# interiors: one face each, four different faces, the outside is face 0
inner = {p: a[p] for p in ["2,2", "10,10", "25,10", "35,3"]}
for p, r in inner.items():
    assert not r["on_boundary"] and len(r["faces"]) == 1, (p, r)
    assert "vertex" not in r and "edge" not in r, (p, r)
ring, hole, out, tri = (inner[p]["faces"][0] for p in ["2,2", "10,10", "25,10", "35,3"])
assert out == 0 and len({ring, hole, out, tri}) == 4, inner
# boundary points: the faces around them, ascending, and the vertex or edge
want = {"0,0": ("vertex", 0, [out, ring]), "10,0": ("edge", 0, [out, ring]),
        "5,10": ("edge", 7, [ring, hole]), "15,15": ("vertex", 6, [ring, hole]),
        "35,8": ("vertex", 10, [out, tri]), "20,7": ("edge", 1, [out, ring])}
for p, (kind, ident, faces) in want.items():
    r = a[p]
    assert r["on_boundary"] is True and r.get(kind) == ident, (p, r)
    assert r["faces"] == sorted(faces), (p, r, faces)
assert a["1000,1000"]["faces"] == [] and not a["1000,1000"]["on_boundary"]
# the batch gives every point the single query's answer
assert len(batch) == len(one)
for b, r in zip(batch, one):
    for key in ("faces", "on_boundary", "exact", "pixel", "inside", "features"):
        assert b.get(key) == r.get(key), (key, b, r)
    assert b.get("vertex") == r.get("vertex") and b.get("edge") == r.get("edge"), (b, r)
# without GEOM: candidates, not exact
assert rough["exact"] is False and rough["on_boundary"] is False, rough
PY

# text form: one face, and the boundary named
run "$INSPECT" --locate 10,0 "$tmp/hole.hpfc"
grep -q "on the boundary: the faces beside edge 0" "$tmp/out" || fail "text: boundary not named: $(cat "$tmp/out")"
run "$INSPECT" --locate 2,2 "$tmp/hole.hpfc"
grep -q "^face  .*(the point's face)" "$tmp/out" || fail "text: one face: $(cat "$tmp/out")"
exit $((failures > 0))
