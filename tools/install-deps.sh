#!/bin/sh
# Installs what building and testing hpfc needs on Debian 12 (clang: the
# ThreadSanitizer build of tools/run-tests.sh and the fuzzers), skipping
# packages that are already there. Runs apt-get as root, or through sudo.
set -eu
PACKAGES="gcc clang meson ninja-build pkg-config python3 libcairo2-dev g++ libgdal-dev gdal-bin libgeos-dev libgeographiclib-dev libdraco-dev draco python3-gdal"
# valgrind: the scaling benchmark's smoke counts instructions with callgrind
# (bench/run-scaling.sh smoke, a step of .ci/run).
PACKAGES="$PACKAGES valgrind"
# The Python package (python/): Debian's interpreter, numpy, pytest, meson-python
# (pip install .), venv (tools/test-python.sh); shapely, pandas, geopandas
# for geometry, frames and the bench against geopandas.sjoin; pyproj (a
# dependency of geopandas, named because the geometry tests project with it);
# fiona, the engine of geopandas.read_file in the GDAL driver's tests;
# distributed (Dask) for hpfc.pack's build in parts on a cluster.
PACKAGES="$PACKAGES python3-dev python3-numpy python3-pytest python3-mesonpy python3-venv python3-shapely python3-pandas python3-geopandas python3-pyproj python3-fiona python3-distributed"
missing=""
for p in $PACKAGES; do
    dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
echo "installing:$missing" >&2
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq $missing >/dev/null
