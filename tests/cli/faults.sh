#!/bin/sh
# Writers that fail cleanly (faults.py): a file size limit, SIGKILL at
# random instants, a read-only directory, for every program that writes a
# file, ogr2ogr -f HPFC through the GDAL driver included when meson names
# its plugin (HPFC_GDAL_DRIVER_PATH). The tools themselves, not lib.sh's
# --force wrappers: faults.py passes --force where it means to.
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
exec python3 "$HERE/faults.py" "$PACK_BIN" "$INSPECT_BIN" "$TESTS"
