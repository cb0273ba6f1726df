#!/bin/sh
# Regenerates the mesh fixtures: OBJ/PLY meshes (here, the encoder's input:
# hpfc-pack reads no OBJ or PLY) and their triangle-edge graphs as .pfc
# (ok/) from gen-mesh (tests/support/gen_mesh.c), and their Draco encodings from
# draco_encoder (Debian 12's `draco` 1.5.5), into ok/ or bad/ by the verdict
# of tests/cli/draco.expect. The outputs are committed, so the tests need
# neither tool.
#
#   sh tests/data/mesh/regen.sh BUILD_DIR
set -eu
gen=$(cd "$1" && pwd)/tests/gen-mesh
cd "$(dirname "$0")"

"$gen" delaunay 7 300 delaunay.obj ok/delaunay.pfc
"$gen" tin 3 16 tin.ply ok/tin.pfc
"$gen" holes 5 14 holes.obj ok/holes.pfc
"$gen" cluster 0 8 cluster.obj ok/cluster.pfc
"$gen" fold 0 4 fold.obj
"$gen" flat 0 5 flat.obj

enc() {
    draco_encoder "$@" >/dev/null
}
# -qp 0: positions stored losslessly; otherwise quantized (default 11 bits).
# -cl 0 encodes connectivity sequentially, the default 7 with Edgebreaker,
# 10 with its valence variant.
enc -i delaunay.obj -o ok/delaunay_lossless.drc -qp 0
enc -i delaunay.obj -o ok/delaunay_lossless_cl0.drc -qp 0 -cl 0
enc -i delaunay.obj -o ok/delaunay_q11.drc
enc -i tin.ply -o ok/tin_lossless.drc -qp 0 -cl 10
enc -i tin.ply -o ok/tin_q11.drc
enc -i tin.ply -o bad/tin_pointcloud.drc -point_cloud
enc -i holes.obj -o ok/holes_lossless.drc -qp 0
enc -i holes.obj -o ok/holes_q14.drc -qp 14
enc -i cluster.obj -o ok/cluster_lossless.drc -qp 0
enc -i cluster.obj -o ok/cluster_q11.drc
enc -i fold.obj -o bad/fold.drc -qp 0
enc -i flat.obj -o bad/flat.drc -qp 0

# hand-made hostile headers (refused before Draco decodes them)
python3 craft_bad.py bad
