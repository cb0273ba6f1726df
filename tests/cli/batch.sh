#!/bin/sh
# hpfc-inspect --locate-batch on tables as GIS users have them (interfaces §4): a header or none, comma, tab, semicolon or blank
# separators, CSV quotes, coordinate and id columns guessed by name or given
# (--lon-col, --lat-col, --id-col, by name or number), extra columns passed
# through, a bad line answered as an error row with its line number while
# the run goes on, every row with "line" and "id"; --format jsonl, csv and
# geojson. The oracle: the single-point query (--locate X,Y --json) for the
# same point, and the input table itself for lines, ids and columns.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"

# a square of side 100 split by its diagonal
printf 'pfc 1\nv 0 0\nv 100 0\nv 100 100\nv 0 100\ne 0 1\ne 1 2\ne 2 3\ne 3 0\ne 0 2\n' >"$tmp/sq.pfc"
"$PACK" --quiet "$tmp/sq.pfc" -o "$tmp/sq.hpfc" || fail "cannot pack"

# agree ROWS TABLE: the rows of --locate-batch (JSON lines) against TABLE,
# a JSON list of [line, id, x, y, {columns}] or [line, id, "error"], and
# every answer against --locate X,Y --json on the same file.
agree() {
    python3 - "$1" "$2" "$INSPECT" "$tmp/sq.hpfc" <<'PY'
import json, subprocess, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
want = json.loads(sys.argv[2])
assert len(rows) == len(want), f"{len(rows)} rows for {len(want)} data lines: {rows}"
for row, w in zip(rows, want):
    assert row["line"] == w[0] and row["id"] == w[1], (row, w)
    if w[2] == "error":
        assert "error" in row and "faces" not in row, row
        continue
    assert "error" not in row, row
    assert (row["x"], row["y"]) == (w[2], w[3]), (row, w)
    assert row.get("columns", {}) == w[4], (row, w)
    one = json.loads(subprocess.run([sys.argv[3], "--locate", f"{w[2]},{w[3]}", "--json",
                                     sys.argv[4]], capture_output=True, check=True).stdout)
    for key in ("line", "id", "columns"):
        row.pop(key, None)
    assert row == one, (row, one)
PY
}

# the two triangles and the outside
printf 'x,y\n25,75\n75,25\n102,102\n' >"$tmp/a.csv"
run "$INSPECT" --locate-batch "$tmp/a.csv" "$tmp/sq.hpfc"
expect_ok "header x,y"
agree "$tmp/out" '[[2,null,25,75,{}],[3,null,75,25,{}],[4,null,102,102,{}]]' ||
    fail "header x,y: rows disagree"
python3 -c '
import json, sys
f = [json.loads(l)["faces"] for l in open(sys.argv[1])]
assert f[0] != f[1] and 0 not in f[0] + f[1] and f[2] == [0], f' "$tmp/out" ||
    fail "the two triangles and the outside are not three faces"

# no header, the old "x,y" form; blanks, tabs and comments
printf '25,75\n# a comment\n\n75,25\n' >"$tmp/b.txt"
run "$INSPECT" --locate-batch "$tmp/b.txt" "$tmp/sq.hpfc"
expect_ok "no header"
agree "$tmp/out" '[[1,null,25,75,{}],[4,null,75,25,{}]]' || fail "no header: rows disagree"
printf '  25   75  extra\n75   25 more\n' >"$tmp/c.txt"
run "$INSPECT" --locate-batch "$tmp/c.txt" "$tmp/sq.hpfc"
expect_ok "blank separators"
agree "$tmp/out" '[[1,null,25,75,{"col3":"extra"}],[2,null,75,25,{"col3":"more"}]]' ||
    fail "blank separators: rows disagree"

# a tab-separated table: id column guessed, the others passed through, a
# bad line and a short line answered as errors, the run going on
printf 'name\tid\tX\tY\tnote\nnw\t7\t25\t75\ta, b\nbad\t8\tabc\t1\t\nshort\t9\t50\nse\t10\t75\t25\t"q"\n' >"$tmp/d.tsv"
run "$INSPECT" --locate-batch "$tmp/d.tsv" "$tmp/sq.hpfc"
expect_ok "tab-separated"
agree "$tmp/out" '[[2,"7",25,75,{"name":"nw","note":"a, b"}],[3,"8","error"],[4,"9","error"],[5,"10",75,25,{"name":"se","note":"q"}]]' ||
    fail "tab-separated: rows disagree"
grep -q '"error":"column .X.: .abc. is not a decimal number"' "$tmp/out" || fail "the error row does not say why"

# columns given by name and by number; CSV quotes; semicolons
printf 'label;east;north\n"a;b";25;75\n' >"$tmp/e.csv"
run "$INSPECT" --locate-batch "$tmp/e.csv" --lon-col east --lat-col NORTH --id-col label "$tmp/sq.hpfc"
expect_ok "--lon-col/--lat-col/--id-col by name"
agree "$tmp/out" '[[2,"a;b",25,75,{}]]' || fail "columns by name: rows disagree"
printf 'p1,75,25\n' >"$tmp/f.csv"
run "$INSPECT" --locate-batch "$tmp/f.csv" --lon-col 2 --lat-col 3 --id-col 1 "$tmp/sq.hpfc"
expect_ok "columns by number"
agree "$tmp/out" '[[1,"p1",75,25,{}]]' || fail "columns by number: rows disagree"
run "$INSPECT" --locate-batch "$tmp/e.csv" --id-col nosuch --lon-col east --lat-col north "$tmp/sq.hpfc"
expect_error "--id-col nosuch" "hpfc-inspect: " 1
printf 'a,b\n1,2\n' >"$tmp/g.csv"
run "$INSPECT" --locate-batch "$tmp/g.csv" "$tmp/sq.hpfc"
expect_error "a header without coordinate columns" "hpfc-inspect: " 1
grep -q "line 1: no longitude/x column" "$tmp/err" || fail "no coordinate column: $(cat "$tmp/err")"

# --format csv: a header, one row a data line, the same answers
run "$INSPECT" --locate-batch "$tmp/d.tsv" --format csv "$tmp/sq.hpfc"
expect_ok "--format csv"
python3 - "$tmp/out" <<'PY' || fail "--format csv: wrong table"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1], newline="")))
assert [r["line"] for r in rows] == ["2", "3", "4", "5"], rows
assert [r["id"] for r in rows] == ["7", "8", "9", "10"], rows
assert rows[0]["note"] == "a, b" and rows[0]["name"] == "nw", rows[0]
assert rows[1]["error"] and not rows[1]["faces"], rows[1]
assert rows[0]["inside"] == "true" and rows[0]["faces"] and not rows[0]["error"], rows[0]
assert rows[0]["faces"] != rows[3]["faces"], rows
PY
# --format geojson: a FeatureCollection of points, answers as properties
run "$INSPECT" --locate-batch "$tmp/d.tsv" --format geojson "$tmp/sq.hpfc"
expect_ok "--format geojson"
python3 - "$tmp/out" <<'PY' || fail "--format geojson: wrong collection"
import json, sys
fc = json.load(open(sys.argv[1]))
assert fc["type"] == "FeatureCollection" and len(fc["features"]) == 4, fc
f0, f1 = fc["features"][0], fc["features"][1]
assert f0["geometry"] == {"type": "Point", "coordinates": [25, 75]}, f0
assert f0["properties"]["line"] == 2 and f0["properties"]["id"] == "7", f0
assert f0["properties"]["name"] == "nw" and f0["properties"]["faces"], f0
assert f1["geometry"] is None and "error" in f1["properties"], f1
PY
: >"$tmp/empty.csv"
run "$INSPECT" --locate-batch "$tmp/empty.csv" --format geojson "$tmp/sq.hpfc"
expect_ok "--format geojson, no points"
check json "$tmp/out" || fail "--format geojson of no points is not JSON"
run "$INSPECT" --locate-batch "$tmp/a.csv" --format xml "$tmp/sq.hpfc"
expect_error "--format xml" "hpfc-inspect: " 2
run "$INSPECT" --lon-col x "$tmp/sq.hpfc"
expect_error "--lon-col without --locate-batch" "hpfc-inspect: " 2

# columns named lon/lat are degrees: placed with the file's CRS (GIS only)
run "$PACK" "$TESTS/data/gis/ok/duplicate_borders.geojson" -o "$tmp/gis.hpfc"
if ! grep -q "not built in" "$tmp/err"; then
    printf 'Longitude,Latitude\n0.5,0.5\n' >"$tmp/ll.csv"
    printf '0.5,0.5\n' >"$tmp/ll.txt"
    run "$INSPECT" --locate-batch "$tmp/ll.csv" "$tmp/gis.hpfc"
    expect_ok "lon/lat columns by name"
    sed 's/"line":2/"line":1/' "$tmp/out" >"$tmp/named.json"
    run "$INSPECT" --locate-batch "$tmp/ll.txt" --lonlat "$tmp/gis.hpfc"
    cmp -s "$tmp/out" "$tmp/named.json" || fail "Longitude/Latitude columns are not taken as degrees"
    grep -q '"lon":0.5,"lat":0.5' "$tmp/out" || fail "--lonlat row lacks lon, lat"
fi

finish
