#!/bin/sh
# hpfc-inspect --render as a map: the window fits the
# data by default (oracle: the vertices' leaves in --export-graph, plus 2 %),
# faces are filled by feature (by face without features; the outside
# white), the SVG's coordinates are the file's user coordinates (a point's
# colour is read at its user coordinates, found with --locate), a PNG comes
# with a world file that places the same point on the same colour,
# --window-lonlat takes degrees and --size sets the image size.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

# fill_at SVG X,Y: the fill colour of the SVG at user coordinates (x, y)
fill_at() {
    python3 - "$1" "$2" <<'PY'
import re, sys
import xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
x, y = map(float, sys.argv[2].split(","))
g = [e for e in root.iter("{http://www.w3.org/2000/svg}g") if e.get("id") == "map"]
assert g and g[0].get("transform") == "scale(1,-1)", "no user-coordinate group"
colour = "#ffffff"
for p in g[0].iter("{http://www.w3.org/2000/svg}path"):
    if p.get("class") != "fill":
        continue
    for m in re.finditer(r"M([-0-9.]+) ([-0-9.]+)H([-0-9.]+)V([-0-9.]+)H[-0-9.]+Z", p.get("d")):
        x0, y0, x1, y1 = map(float, m.groups())
        if min(x0, x1) <= x <= max(x0, x1) and min(y0, y1) <= y <= max(y0, y1):
            colour = p.get("fill")
print(colour)
PY
}

# xy FILE X,Y | --lonlat LON,LAT: the user coordinates --locate reports
user_xy() {
    "$INSPECT" "$@" --json | python3 -c 'import json,sys; a=json.load(sys.stdin); print(repr(a["x"]) + "," + repr(a["y"]))'
}

# ---- a .pfc map: the square split by its diagonal, faces by face id ----------
printf 'pfc 1\nv 0 0\nv 100 0\nv 100 100\nv 0 100\ne 0 1\ne 1 2\ne 2 3\ne 3 0\ne 0 2\n' >"$tmp/sq.pfc"
"$PACK" --quiet "$tmp/sq.pfc" -o "$tmp/sq.hpfc" || fail "cannot pack"
"$INSPECT" --export-graph "$tmp/sq.json" "$tmp/sq.hpfc" >/dev/null || fail "cannot export"
run "$INSPECT" --render "$tmp/sq.svg" --json "$tmp/sq.hpfc"
expect_ok "--render SVG, default window"
python3 - "$tmp/out" "$tmp/sq.json" "$tmp/sq.svg" <<'PY' || fail "the default window does not fit the data"
import json, sys
import xml.etree.ElementTree as ET
rep, graph = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
boxes = [v["box"] for v in graph["vertices"]]
x0, y0 = min(b[0] for b in boxes), min(b[1] for b in boxes)
x1, y1 = max(b[2] for b in boxes), max(b[3] for b in boxes)
w = rep["window"]
mx, my = 0.02 * (x1 - x0), 0.02 * (y1 - y0)
assert w[0] <= x0 and w[1] <= y0 and w[2] >= x1 and w[3] >= y1, (w, (x0, y0, x1, y1))
assert abs(w[0] - (x0 - mx)) < 1e-6 and abs(w[2] - (x1 + mx)) < 1e-6, (w, x0, x1)
assert rep["colour"] == "face", rep
vb = [float(v) for v in ET.parse(sys.argv[3]).getroot().get("viewBox").split()]
assert abs(vb[0] - w[0]) < 1e-3 and abs(-vb[1] - w[3]) < 1e-3, (vb, w)
assert abs(vb[2] - (w[2] - w[0])) < 1e-3 and abs(vb[3] - (w[3] - w[1])) < 1e-3, (vb, w)
PY
nw=$(fill_at "$tmp/sq.svg" 25,75) se=$(fill_at "$tmp/sq.svg" 75,25) out=$(fill_at "$tmp/sq.svg" 103,50)
[ "$nw" != "$se" ] && [ "$nw" != "#ffffff" ] && [ "$se" != "#ffffff" ] ||
    fail "the triangles are not two coloured faces: $nw $se"
[ "$out" = "#ffffff" ] || fail "the outside is $out, not white"

# --size, --window in user coordinates
run "$INSPECT" --render "$tmp/w.svg" --size 300 --window 0,0,50,100 --json "$tmp/sq.hpfc"
expect_ok "--window --size"
python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); assert (r["width"], r["height"]) == (300, 600), r' \
    "$tmp/out" || fail "--size 300 with a 1:2 window is not 300x600"
[ "$(fill_at "$tmp/w.svg" 25,75)" = "$nw" ] || fail "--window: a face changed colour"

# PNG: a world file that puts (25, 75) on the north-west triangle's colour
run "$INSPECT" --render "$tmp/sq.png" --size 400 "$tmp/sq.hpfc"
if [ "$rc" -eq 0 ]; then
    [ -s "$tmp/sq.pgw" ] || fail "no world file sq.pgw beside sq.png"
    python3 - "$HERE" "$tmp/sq.png" "$tmp/sq.pgw" "$nw" "$se" <<'PY' || fail "the world file does not place the picture"
import struct, sys, zlib
sys.path.insert(0, sys.argv[1])
from views_check import png_rows
data = open(sys.argv[2], "rb").read()
pos, idat = 8, b""
while pos < len(data):
    n, kind = struct.unpack(">I4s", data[pos:pos + 8])
    if kind == b"IHDR":
        w, h, depth, ctype = struct.unpack(">IIBB", data[pos + 8:pos + 18])
    elif kind == b"IDAT":
        idat += data[pos + 8:pos + 8 + n]
    pos += 12 + n
bpp = {2: 3, 6: 4}[ctype]
rows = png_rows(zlib.decompress(idat), w, h, bpp)
a, d, b, e, c, f = (float(v) for v in open(sys.argv[3]).read().split())
assert a > 0 and e == -a and b == 0 and d == 0, (a, e)
def colours(x, y):
    """the colours around the pixel of (x, y): a leaf's outline may cross it"""
    i, j = round((x - c) / a), round((y - f) / e)
    return {"#%02x%02x%02x" % tuple(rows[j + dj][(i + di) * bpp:(i + di) * bpp + 3])
            for di in range(-2, 3) for dj in range(-2, 3)}
assert sys.argv[4] in colours(25, 75), (colours(25, 75), sys.argv[4], a, c, f, w, h)
assert sys.argv[5] in colours(75, 25), (colours(75, 25), sys.argv[5])
assert sys.argv[4] not in colours(75, 25), (colours(75, 25), sys.argv[4:])
assert "#ffffff" in colours(103, 50), colours(103, 50)
PY
elif grep -q 'no PNG output' "$tmp/err"; then
    echo "note: this build has no cairo; PNG not checked"
else
    fail "--render PNG: exit status $rc: $(cat "$tmp/err")"
fi

# ---- GIS features: colour by feature, --window-lonlat -------------------------
run "$PACK" "$TESTS/data/gis/ok/duplicate_borders.geojson" -o "$tmp/probe.hpfc"
if grep -q "not built in" "$tmp/err"; then
    echo "GIS input not built in: the feature checks skipped"
    finish
fi
cat >"$tmp/states.json" <<'TOPO'
{"type": "Topology",
 "objects": {"states": {"type": "GeometryCollection", "geometries": [
   {"type": "Polygon", "arcs": [[0, 1]], "properties": {"name": "West"}},
   {"type": "Polygon", "arcs": [[2, -1]], "properties": {"name": "East"}}]}},
 "arcs": [[[-100, 40], [-100, 45]],
          [[-100, 45], [-110, 45], [-110, 40], [-100, 40]],
          [[-100, 40], [-90, 40], [-90, 45], [-100, 45]]]}
TOPO
"$PACK" --quiet --key name "$tmp/states.json" -o "$tmp/st.hpfc" || fail "cannot pack the states"
west=$(user_xy --locate-lonlat -105,42.5 "$tmp/st.hpfc") east=$(user_xy --locate-lonlat -95,42.5 "$tmp/st.hpfc")
south=$(user_xy --locate-lonlat -100,39.7 "$tmp/st.hpfc")
run "$INSPECT" --render "$tmp/st.svg" --json "$tmp/st.hpfc"
expect_ok "--render the states"
grep -q '"colour":"feature"' "$tmp/out" || fail "the states are not coloured by feature"
cw=$(fill_at "$tmp/st.svg" "$west") ce=$(fill_at "$tmp/st.svg" "$east") cs=$(fill_at "$tmp/st.svg" "$south")
[ "$cw" != "$ce" ] && [ "$cw" != "#ffffff" ] && [ "$ce" != "#ffffff" ] ||
    fail "West and East are not two feature colours: $cw $ce"
[ "$cs" = "#ffffff" ] || fail "south of the states (no feature) is $cs, not white"
# --window-lonlat around East only: East's centre inside, West's outside
run "$INSPECT" --render "$tmp/east.svg" --window-lonlat -99,40,-91,45 --json "$tmp/st.hpfc"
expect_ok "--window-lonlat"
python3 - "$tmp/out" "$west" "$east" <<'PY' || fail "--window-lonlat: wrong window"
import json, sys
w = json.load(open(sys.argv[1]))["window"]
inside = lambda p: w[0] <= p[0] <= w[2] and w[1] <= p[1] <= w[3]
west, east = (tuple(map(float, a.split(","))) for a in sys.argv[2:4])
assert inside(east) and not inside(west), (w, west, east)
PY
[ "$(fill_at "$tmp/east.svg" "$east")" = "$ce" ] || fail "--window-lonlat: East changed colour"
run "$INSPECT" --render "$tmp/x.svg" --window-lonlat -99,40,-91,45 --window 0,0,1,1 "$tmp/st.hpfc"
expect_error "--window with --window-lonlat" "hpfc-inspect: " 2
run "$INSPECT" --render "$tmp/x.svg" --window-lonlat -99,40,-91 "$tmp/st.hpfc"
expect_error "--window-lonlat with three numbers" "hpfc-inspect: " 2
run "$INSPECT" --render "$tmp/x.svg" --window-lonlat 0,0,1,1 "$tmp/sq.hpfc"
expect_error "--window-lonlat on a file without CRS" "hpfc-inspect: " 1

finish
