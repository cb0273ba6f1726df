#!/bin/sh
# Linking faces to features from the topology, feature ids that
# do not depend on the input format, stored attributes (ATTR) and the edges'
# features (EDGF):
#  - nested rings (islands in lakes in islands), an archipelago inside a
#    coast's box, overlapping features, a hole holding another feature,
#    with and without crossing rings, --vertices all and junctions: the
#    topological linking gives byte-identical files to the pre-1.2 witness
#    method (--link witness) and on 1 and 3 threads (--threads), and
#    --locate-batch agrees with a naive even-odd point-in-polygon oracle
#    (link_oracle.py);
#  - GeoJSON, Shapefile and GeoPackage copies of the counties (ogr2ogr) give
#    the same fids, keys and attributes, each its own source_fid;
#  - --fields stores typed values that GDAL reads back (feature_oracle.py
#    for the points, GDAL for the values); --key a,b joins them;
#  - a line layer: its features are recorded, no face lies in them;
#  - rings that turn back inside an edge or pass no vertex of the map name
#    every edge they run along.
# Skipped (exit 77) without GIS input or without Python's GDAL bindings.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
GIS=$TESTS/data/gis
counties=$GIS/counties_ne.geojson

run "$PACK" "$GIS/ok/duplicate_borders.geojson" -o "$tmp/probe.hpfc"
if grep -q "not built in" "$tmp/err"; then
    echo "GIS input not built in: skipped"
    exit 77
fi
py=
for cand in python3 /usr/bin/python3; do
    if "$cand" -c 'from osgeo import ogr' 2>/dev/null; then
        py=$cand
        break
    fi
done
if [ -z "$py" ] || ! command -v ogr2ogr >/dev/null; then
    echo "no python3 with osgeo or no ogr2ogr: skipped"
    exit 77
fi

# --- nested rings: topology == witness, and the naive oracle -----------------
for kind in nested crossing; do
    python3 "$HERE/link_oracle.py" make "$tmp/$kind.geojson" 7 "$kind"
    python3 "$HERE/link_oracle.py" points "$tmp/$kind.geojson" 11 500 "$tmp/p.txt" "$tmp/want.json"
    for v in all junctions; do
        run "$PACK" --json --vertices "$v" "$tmp/$kind.geojson" -o "$tmp/t.hpfc"
        expect_ok "$kind $v: pack"
        cp "$tmp/out" "$tmp/report.json"
        "$PACK" --link witness --vertices "$v" "$tmp/$kind.geojson" -o "$tmp/w.hpfc" \
            >/dev/null 2>&1 || fail "$kind $v: pack with the witness method"
        cmp -s "$tmp/t.hpfc" "$tmp/w.hpfc" || fail "$kind $v: topology and witness linking differ"
        # validation, the build, the faces and their check on one thread and
        # on three: the same bytes
        for n in 1 3; do
            "$PACK" --threads "$n" --vertices "$v" "$tmp/$kind.geojson" -o "$tmp/n$n.hpfc" \
                >/dev/null 2>&1 || fail "$kind $v: pack on $n threads"
            cmp -s "$tmp/t.hpfc" "$tmp/n$n.hpfc" || fail "$kind $v: $n threads give other bytes"
        done
        python3 - "$tmp/report.json" "$kind" <<'PY' || fail "$kind $v: link report"
import json, sys
r = json.load(open(sys.argv[1]))
l = r["linking"]
assert l["method"] == "topology" and l["conflicts"] == 0, l
# nearly every face is reached over edges, not by a witness point
assert l["faces_walked"] >= r["faces"] // 2, (l, r["faces"])
assert r["features_recorded"] == (8 if sys.argv[2] == "crossing" else 6), r["features_recorded"]
assert r["polygon_features"] == r["features_recorded"] - 1, r
PY
        run "$INSPECT" --locate-batch "$tmp/p.txt" "$tmp/t.hpfc"
        expect_ok "$kind $v: --locate-batch"
        python3 - "$tmp/out" "$tmp/want.json" <<'PY' || fail "$kind $v: --locate-batch disagrees with the naive oracle"
import json, sys
answers = [json.loads(line) for line in open(sys.argv[1])]
want = json.load(open(sys.argv[2]))
assert len(answers) == len(want)
private = nested = 0
for k, (a, w) in enumerate(zip(answers, want)):
    got = sorted(f["fid"] for f in a["features"])
    if a["private"]:
        private += 1
        assert got == w, f"point {k} ({a['x']}, {a['y']}): got {got}, want {w}"
    else:
        assert all(f in got for f in w), f"point {k}: {w} not among {got}"
    nested += len(w) >= 2
assert private >= len(answers) // 4, private
assert nested >= 10, nested  # overlapping features really overlap
PY
    done
done

# --- fids do not depend on the input format ---------------------------------
ogr2ogr -f "ESRI Shapefile" "$tmp/c.shp" "$counties" 2>/dev/null || fail "ogr2ogr to Shapefile"
ogr2ogr -f GPKG "$tmp/c.gpkg" "$counties" 2>/dev/null || fail "ogr2ogr to GeoPackage"
"$py" "$HERE/feature_oracle.py" "$counties" name 5 300 "$tmp/cp.txt" "$tmp/cwant.json" ||
    fail "feature_oracle.py"
for src in "$counties" "$tmp/c.shp" "$tmp/c.gpkg"; do
    name=$(basename "$src")
    run "$PACK" --invalid node --key name,fips --fields name,fips "$src" -o "$tmp/$name.hpfc"
    expect_ok "pack $name"
    "$INSPECT" --locate-batch "$tmp/cp.txt" --lonlat "$tmp/$name.hpfc" >"$tmp/$name.out" ||
        fail "--locate-batch $name"
done
python3 - "$tmp/counties_ne.geojson.out" "$tmp/c.shp.out" "$tmp/c.gpkg.out" "$tmp/cwant.json" <<'PY' || fail "fids differ between GeoJSON, Shapefile and GeoPackage"
import json, sys
runs = [[json.loads(line) for line in open(p)] for p in sys.argv[1:4]]
want = json.load(open(sys.argv[4]))
def strip(a):
    return [(f["fid"], f["key"], f["attributes"]["name"], f["attributes"]["fips"])
            for f in a["features"]]
seen = 0
for k, answers in enumerate(zip(*runs)):
    geojson, shp, gpkg = (strip(a) for a in answers)
    assert geojson == shp == gpkg, (k, geojson, shp, gpkg)
    for f in answers[0]["features"]:
        assert f["key"] == f["attributes"]["name"] + "," + f["attributes"]["fips"], f
    if answers[0]["private"]:
        # fid = position in the layer = GDAL's FID of the GeoJSON copy
        assert [(f[0], f[2]) for f in geojson] == [(w["fid"], w["key"]) for w in want[k]], k
    seen += bool(geojson)
    # each copy keeps its own source FID: a GeoPackage counts from 1
    for a, b in zip(answers[0]["features"], answers[2]["features"]):
        assert b["attributes"]["source_fid"] == a["attributes"]["source_fid"] + 1, (a, b)
assert seen >= len(want) // 2, seen
PY

# --- --fields all: typed values as GDAL reads them ---------------------------
python3 - "$tmp/typed.geojson" <<'PY'
import json, sys
feats = []
for i in range(6):
    x = i * 2.0
    ring = [[x, 0], [x + 1, 0], [x + 1, 1], [x, 1], [x, 0]]
    props = {"n": i * 7 - 3, "r": i / 3 + 0.1, "s": f"name {i} \u00e9", "d": f"2020-0{i + 1}-15"}
    if i == 2:
        props["r"] = None
    feats.append({"type": "Feature", "properties": props,
                  "geometry": {"type": "Polygon", "coordinates": [ring]}})
json.dump({"type": "FeatureCollection", "features": feats}, open(sys.argv[1], "w"))
PY
run "$PACK" --fields all "$tmp/typed.geojson" -o "$tmp/typed.hpfc"
expect_ok "--fields all"
printf '0.5,0.5\n2.5,0.5\n4.5,0.5\n6.5,0.5\n8.5,0.5\n10.5,0.5\n' >"$tmp/tp.txt"
run "$INSPECT" --locate-batch "$tmp/tp.txt" --lonlat "$tmp/typed.hpfc"
expect_ok "--fields all: --locate-batch"
"$py" - "$tmp/out" "$tmp/typed.geojson" <<'PY' || fail "--fields all: values differ from GDAL's"
import json, sys
from osgeo import ogr
answers = [json.loads(line) for line in open(sys.argv[1])]
ds = ogr.Open(sys.argv[2])  # kept: the layer dies with its dataset
layer = ds.GetLayer(0)
for k, f in enumerate(layer):
    feats = answers[k]["features"]
    assert len(feats) == 1 and feats[0]["fid"] == k, answers[k]
    a = feats[0]["attributes"]
    assert a["source_fid"] == f.GetFID()
    assert a["n"] == f.GetField("n") and isinstance(a["n"], int), a
    assert a["r"] == f.GetField("r"), a  # exact: shortest round-trip form
    assert a["s"] == f.GetField("s"), a
    d = f.GetField("d").replace("/", "-")
    assert a["d"] == d, (a["d"], d)
PY
run "$PACK" --fields nosuch "$counties" --invalid node -o "$tmp/nf.hpfc"
expect_error "--fields unknown field" "hpfc-pack: $counties: --fields nosuch: layer" 1
run "$PACK" --fields "a,,b" "$counties" -o "$tmp/nf.hpfc"
[ "$rc" = 2 ] || fail "--fields a,,b is not a usage error"

# --- a line layer: features recorded, faces in none --------------------------
python3 - "$tmp/lines.geojson" <<'PY'
import json, sys
feats = [{"type": "Feature", "properties": {"name": f"river {i}"},
          "geometry": {"type": "LineString",
                       "coordinates": [[i * 0.1, 0], [i * 0.1 + 0.05, 0.5], [i * 0.1, 1]]}}
         for i in range(5)]
json.dump({"type": "FeatureCollection", "features": feats}, open(sys.argv[1], "w"))
PY
run "$PACK" --json --key name "$tmp/lines.geojson" -o "$tmp/lines.hpfc"
expect_ok "pack a line layer"
python3 - "$tmp/out" <<'PY' || fail "line layer: features"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["features_recorded"] == 5 and r["polygon_features"] == 0, r
assert r["faces_with_features"] == 0, r
assert r["edges_with_features"] == r["edges"], r
PY
run "$INSPECT" --verify "$tmp/lines.hpfc"
expect_ok "--verify a line layer"

# --- lines that cross: the pieces noding cuts keep their features ------------
python3 - "$tmp/cross.geojson" <<'PY'
import json, sys
lines = {"a": [[0, 0], [10, 10]], "b": [[0, 10], [10, 0]], "c": [[0, 3.3], [4, 3.2], [10, 3.1]]}
feats = [{"type": "Feature", "properties": {"name": k},
          "geometry": {"type": "LineString", "coordinates": c}} for k, c in lines.items()]
json.dump({"type": "FeatureCollection", "features": feats}, open(sys.argv[1], "w"))
PY
run "$PACK" --json --key name --projection none "$tmp/cross.geojson" -o "$tmp/cross.hpfc"
expect_ok "pack crossing lines"
python3 - "$tmp/out" <<'PY' || fail "crossing lines: an edge noding cut names no feature"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["noding"] != "none", r["noding"]
assert r["edges_with_features"] == r["edges"], (r["edges_with_features"], r["edges"])
PY
# a point just beside each piece: its leaf's crossings name that line
for q in "1,1.001 a" "8,8.01 a" "1,8.99 b" "9,1.01 b" "5,3.2 c" "9.9,3.1 c" "2,3.26 c"; do
    run "$INSPECT" --json --locate "${q% *}" "$tmp/cross.hpfc"
    expect_ok "--locate ${q% *}"
    python3 - "$tmp/out" "${q#* }" <<'PY' || fail "crossing lines: --locate ${q% *} does not name ${q#* }"
import json, sys
a = json.load(open(sys.argv[1]))
assert sys.argv[2] in [f.get("key") for f in a.get("along", [])], a
PY
done

# --- rings that turn back inside an edge, a ring through no vertex -----------
# P's spike runs out along the line L and back from a point inside L's edge;
# deg has no area and lies along Q's side between points of degree 2, so no
# vertex of the map is on it. Both still name every edge they run along.
python3 - "$tmp/spike.geojson" <<'PY'
import json, sys
rings = {"P": [[0, 0], [10, 0], [10, 5], [14, 5], [10, 5], [10, 10], [0, 10], [0, 0]],
         "Q": [[20, 0], [30, 0], [30, 10], [20, 10], [20, 0]],
         "deg": [[22, 0], [25, 0], [23, 0], [22, 0]]}
feats = [{"type": "Feature", "properties": {"name": k},
          "geometry": {"type": "Polygon", "coordinates": [r]}} for k, r in rings.items()]
feats.append({"type": "Feature", "properties": {"name": "L"},
              "geometry": {"type": "LineString", "coordinates": [[12, 5], [16, 5]]}})
json.dump({"type": "FeatureCollection", "features": feats}, open(sys.argv[1], "w"))
PY
run "$PACK" --key name --projection none "$tmp/spike.geojson" -o "$tmp/spike.hpfc"
expect_ok "pack rings that turn back"
"$PACK" --link witness --key name --projection none "$tmp/spike.geojson" -o "$tmp/spike_w.hpfc" \
    >/dev/null 2>&1 || fail "rings that turn back: pack with the witness method"
cmp -s "$tmp/spike.hpfc" "$tmp/spike_w.hpfc" || fail "rings that turn back: topology and witness differ"
for q in "11,5.001 P -" "13,5.001 L,P -" "15.9,5.001 L,P -" "5,5 - P" "21,0.001 Q,deg Q" \
    "24,0.001 Q,deg Q" "25,5 - Q"; do
    set -- $q
    run "$INSPECT" --json --locate "$1" "$tmp/spike.hpfc"
    expect_ok "--locate $1"
    python3 - "$tmp/out" "$2" "$3" <<'PY' || fail "rings that turn back: --locate $1 does not give along $2, in $3"
import json, sys
a = json.load(open(sys.argv[1]))
along = ",".join(sorted(f["key"] for f in a.get("along", []))) or "-"
inside = ",".join(sorted(f["key"] for f in a.get("features", []))) or "-"
assert (along, inside) == (sys.argv[2], sys.argv[3]), (along, inside)
PY
done

finish
