#!/usr/bin/env python3
"""Writes the hand-made hostile Draco files of bad/ (regen.sh
calls it): tiny files whose headers declare sizes Draco would allocate
before reading any data, which hpfc-pack refuses up front
(hpfc-pack/draco_input.cc, "declared sizes").

    python3 tests/data/mesh/craft_bad.py tests/data/mesh/bad
"""
import os
import sys


def varint(v):
    out = bytearray()
    while True:
        b = v & 0x7F
        v >>= 7
        out.append(b | (0x80 if v else 0))
        if not v:
            return bytes(out)


def header(major, minor, method, flags=0):
    # "DRACO", version, encoder type 1 (triangle mesh), method, flags (u16)
    return b"DRACO" + bytes([major, minor, 1, method]) + flags.to_bytes(2, "little")


def u32(v):
    return v.to_bytes(4, "little")


PADDING = bytes(64)  # where the symbols would be: never read
FACES = 100_000_000

FILES = {
    # Edgebreaker 2.2: traversal type; varint vertices, faces; attribute
    # data count (u8); varint symbols, split symbols. Draco 1.5.5 sizes its
    # corner table from these: 2.3 GB resident for 100 M faces.
    "declares_faces_edgebreaker.drc": header(2, 2, 1) + b"\x00" + varint(3) + varint(FACES)
    + b"\x00" + varint(FACES) + varint(0) + PADDING,
    # Edgebreaker 1.x: the same with uint32 counts, after the new-vertex count
    "declares_faces_edgebreaker_v1.drc": header(1, 2, 1) + b"\x00" + u32(0) + u32(3) + u32(FACES)
    + b"\x00" + u32(FACES) + u32(0) + PADDING,
    # sequential 2.2: varint faces, varint points (Draco bounds the faces itself)
    "declares_points_sequential.drc": header(2, 2, 0) + varint(1) + varint(4_000_000_000) + b"\x01\x00\x01\x02" + PADDING,
    # metadata: one file entry claiming 4 GB
    "metadata_entry_too_long.drc": header(2, 2, 1, 0x8000) + varint(0) + varint(1) + b"\x01a" + varint(0xFFFFFFFF) + PADDING,
    # metadata: sub-elements nested 40 deep
    "metadata_too_deep.drc": header(2, 2, 1, 0x8000) + varint(0)
    + (varint(0) + varint(1) + b"\x01s") * 40 + (varint(0) + varint(0)) * 41 + PADDING,
}

for name, data in FILES.items():
    with open(os.path.join(sys.argv[1], name), "wb") as f:
        f.write(data)
