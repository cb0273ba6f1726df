#!/bin/sh
# The OGR driver HPFC (gdal/, interfaces §7) from GDAL's own tools and from
# Python, with the build's plugin found through GDAL_DRIVER_PATH (set by
# meson): ogrinfo -al -so, -spat, -where; ogr2ogr to GPKG and GeoJSON and
# back; osgeo.ogr random reads; fiona and geopandas reads with bbox=;
# every feature equal to hpfc-inspect --export's; spatial filters equal to
# GEOS on the exported shapes; ogr2ogr -f HPFC the same bytes as
# hpfc-pack; damaged files give an error, never a crash
# (gdal_oracle.py does the comparing). On the shipped sample
# (data/delaunay-4000.pfc: faces and edges only) and on the public layers
# of tests/data/gis (us-atlas counties, world-atlas countries). Skipped
# (exit 77) without the driver or Python's GDAL bindings.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
GIS=$TESTS/data/gis

if [ -z "${GDAL_DRIVER_PATH:-}" ] || [ ! -f "$GDAL_DRIVER_PATH/ogr_HPFC.so" ]; then
    echo "the GDAL driver is not built: skipped"
    exit 77
fi
py=
for cand in /usr/bin/python3 python3; do
    if "$cand" -c 'from osgeo import ogr; import fiona, geopandas, shapely' 2>/dev/null; then
        py=$cand
        break
    fi
done
if [ -z "$py" ]; then
    echo "no python3 with osgeo, fiona and geopandas: skipped"
    exit 77
fi

# expect_gdal WHAT: exit 0, and nothing on stderr but GPKG's warning on a
# fid 0 (which it stores all the same: the oracle compares the fids)
expect_gdal() {
    if [ "$rc" -ne 0 ] || grep -v "Feature id not preserved" "$tmp/err" | grep -q .; then
        fail "$1: exit status $rc, stderr: $(head -c 300 "$tmp/err")"
    fi
}

run ogrinfo --formats
grep -q '^ *HPFC -vector- (rw' "$tmp/out" || fail "ogrinfo --formats does not list HPFC read-write: $(cat "$tmp/out")"

# the shipped sample and two public layers
run "$PACK" "$TESTS/../data/delaunay-4000.pfc" -o "$tmp/sample.hpfc"
expect_ok "pack the sample"
run "$PACK" --key name --fields all "$GIS/counties_ne.geojson" -o "$tmp/counties.hpfc"
expect_ok "pack counties"
run "$PACK" --key name --fields all "$GIS/countries_world.geojson" -o "$tmp/world.hpfc"
expect_ok "pack countries"
run "$PACK" --key i --fields all "$GIS/ok/lines_crossing.geojson" -o "$tmp/lines.hpfc"
expect_ok "pack lines"
# two layers of one file: counties as polygons, their borders as lines
run ogr2ogr -f GPKG "$tmp/two.gpkg" "$GIS/counties_ne.geojson" -nln polys
expect_gdal "two.gpkg polys"
run ogr2ogr -f GPKG -update "$tmp/two.gpkg" "$GIS/counties_ne.geojson" -nln borders \
    -dialect sqlite -sql "SELECT name, ST_Multi(ST_Boundary(geometry)) AS geometry FROM counties_ne" \
    -nlt MULTILINESTRING
expect_gdal "two.gpkg borders"
run "$PACK" --key name --fields all "$tmp/two.gpkg" -o "$tmp/two.hpfc"
expect_ok "pack two layers"

for m in sample counties world lines two; do
    run ogrinfo -ro -al -so "$tmp/$m.hpfc"
    expect_ok "ogrinfo -al -so $m"
    grep -q "using driver \`HPFC' successful" "$tmp/out" || fail "$m: not opened by HPFC"
    cp "$tmp/out" "$tmp/$m.so.txt"
    # the reference: what hpfc-inspect --export writes
    if [ "$m" != sample ]; then
        run "$INSPECT" --export "$tmp/$m.export.gpkg" "$tmp/$m.hpfc"
        expect_ok "$m: --export"
    fi
    run "$INSPECT" --export-faces "$tmp/$m.faces.gpkg" "$tmp/$m.hpfc"
    expect_ok "$m: --export-faces"
    run ogr2ogr -f GPKG "$tmp/$m.gpkg" "$tmp/$m.hpfc"
    expect_gdal "$m: ogr2ogr -f GPKG"
    run ogr2ogr -f GeoJSON "$tmp/$m.geojson" "$tmp/$m.hpfc" faces
    expect_ok "$m: ogr2ogr -f GeoJSON"
done

# -where and -spat through ogrinfo, checked in the oracle
run ogrinfo -ro -q "$tmp/counties.hpfc" counties_ne -where "name LIKE 'New%'"
expect_ok "ogrinfo -where"
cp "$tmp/out" "$tmp/where.txt"
run ogrinfo -ro -q "$tmp/counties.hpfc" counties_ne -spat -73 41 -72 42
expect_ok "ogrinfo -spat"
cp "$tmp/out" "$tmp/spat.txt"

# writing: through GPKG and back, the bytes of hpfc-pack
run ogr2ogr -f GPKG "$tmp/src.gpkg" "$GIS/counties_ne.geojson" -nln counties
expect_ok "source GPKG"
run ogr2ogr -f HPFC "$tmp/written.hpfc" "$tmp/src.gpkg" -dsco KEY=name
expect_ok "ogr2ogr -f HPFC"
run "$PACK" --key name --fields all "$tmp/src.gpkg" -o "$tmp/packed.hpfc"
expect_ok "hpfc-pack of the same GPKG"
cmp "$tmp/written.hpfc" "$tmp/packed.hpfc" >/dev/null || fail "ogr2ogr -f HPFC and hpfc-pack differ"
# straight from GeoJSON too (no FID column there: ogr2ogr numbers them as
# GeoJSON's reader does)
run ogr2ogr -f HPFC "$tmp/written_gj.hpfc" "$GIS/counties_ne.geojson" -dsco KEY=name
expect_ok "ogr2ogr -f HPFC from GeoJSON"
run "$PACK" --key name --fields all "$GIS/counties_ne.geojson" -o "$tmp/packed_gj.hpfc"
expect_ok "hpfc-pack of the GeoJSON"
cmp "$tmp/written_gj.hpfc" "$tmp/packed_gj.hpfc" >/dev/null || fail "ogr2ogr -f HPFC and hpfc-pack differ (GeoJSON)"
run ogr2ogr -f GPKG "$tmp/src2.gpkg" "$GIS/countries_world.geojson"
expect_ok "source GPKG 2"
run ogr2ogr -f HPFC "$tmp/written2.hpfc" "$tmp/src2.gpkg" -dsco VERTICES=all -dsco LEAF_POINTS=4 \
    -dsco PROJECTION=lcc -dsco LAYOUT=paper -dsco KEY=name
expect_ok "ogr2ogr -f HPFC with options"
run "$PACK" --vertices all --leaf-points 4 --projection lcc --layout paper --key name --fields all \
    "$tmp/src2.gpkg" -o "$tmp/packed2.hpfc"
expect_ok "hpfc-pack with options"
cmp "$tmp/written2.hpfc" "$tmp/packed2.hpfc" >/dev/null || fail "ogr2ogr -f HPFC and hpfc-pack differ (options)"
# the threads (NUM_THREADS, else GDAL_NUM_THREADS) change nothing in the bytes
for threads in "-dsco NUM_THREADS=1" "-dsco NUM_THREADS=3" "--config GDAL_NUM_THREADS 2"; do
    # shellcheck disable=SC2086 # the option and its value, two words
    run ogr2ogr -f HPFC "$tmp/threads.hpfc" "$tmp/src2.gpkg" -dsco VERTICES=all -dsco LEAF_POINTS=4 \
        -dsco PROJECTION=lcc -dsco LAYOUT=paper -dsco KEY=name $threads
    expect_ok "ogr2ogr -f HPFC $threads"
    cmp "$tmp/threads.hpfc" "$tmp/packed2.hpfc" >/dev/null || fail "$threads: not hpfc-pack's bytes"
    rm -f "$tmp/threads.hpfc"
done
# back: the driver's GPKG of counties packed again keeps every feature
run ogr2ogr -f HPFC "$tmp/back.hpfc" "$tmp/counties.gpkg" counties_ne -dsco KEY=name
expect_gdal "ogr2ogr -f HPFC from the driver's own GPKG"
# refused: a bad option, a missing folder; nothing is left behind
run ogr2ogr -f HPFC "$tmp/bad.hpfc" "$tmp/src.gpkg" -dsco VERTICES=some
[ -e "$tmp/bad.hpfc" ] && fail "a refused VERTICES left a file"
grep -q "VERTICES=some" "$tmp/err" || fail "VERTICES=some: no message: $(cat "$tmp/err")"
for threads in "-dsco NUM_THREADS=0" "-dsco NUM_THREADS=65" "-dsco NUM_THREADS=two" \
    "--config GDAL_NUM_THREADS -1"; do
    # shellcheck disable=SC2086
    run ogr2ogr -f HPFC "$tmp/bad.hpfc" "$tmp/src.gpkg" $threads
    [ "$rc" -ne 0 ] && [ ! -e "$tmp/bad.hpfc" ] && grep -q "NUM_THREADS=" "$tmp/err" ||
        fail "$threads: not refused cleanly: $rc $(cat "$tmp/err")"
done
run ogr2ogr -f HPFC "$tmp/no/such/dir.hpfc" "$tmp/src.gpkg"
[ "$rc" -ne 0 ] && grep -q "no such folder" "$tmp/err" || fail "a missing folder: $rc $(cat "$tmp/err")"

# where FEAT lies in counties.hpfc: the oracle rewrites its fids out of
# file order (as a 1.1 writer's source FIDs may be) to look them up
"$INSPECT_BIN" "$tmp/counties.hpfc" | awk '$1 == "FEAT" { print $2 }' >"$tmp/counties.feat"
[ -s "$tmp/counties.feat" ] || fail "no FEAT section listed for counties.hpfc"

"$py" "$TESTS/cli/gdal_oracle.py" "$tmp" || fail "gdal_oracle.py"
finish
