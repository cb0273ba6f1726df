"""Checks used by tests/cli/inspect_views.sh (hpfc-inspect queries).

    views_check.py same OUT GOLDEN     OUT and GOLDEN hold equal JSON values, "file"
                                       and "seconds" keys aside (they vary per run)
    views_check.py png FILE W H        FILE is a PNG of W x H pixels that is not blank
                                       (its pixels take more than one colour)
    views_check.py svg FILE W H        FILE is well-formed XML with an <svg> root of
                                       width W and height H, with edges drawn

Exit status 0 when the check holds, 1 with a one-line reason otherwise.
"""
import json
import struct
import sys
import xml.etree.ElementTree as ET
import zlib

VARYING = ("file", "seconds")


def fail(msg):
    print("views_check.py: " + msg, file=sys.stderr)
    sys.exit(1)


def load(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        fail(f"{path}: not valid JSON: {e}")


def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if k not in VARYING}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v


def same(out, golden):
    a, b = strip(load(out)), strip(load(golden))
    if a != b:
        fail(f"{out} differs from {golden}:\n  got      {json.dumps(a)}\n  expected {json.dumps(b)}")


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    return a if pa <= pb and pa <= pc else b if pb <= pc else c


def png_rows(data, width, height, bpp):
    """The unfiltered scanlines of 8-bit PNG image data (RFC 2083 §6)."""
    stride = width * bpp
    rows, prev, pos = [], bytearray(stride), 0
    for _ in range(height):
        kind, line = data[pos], bytearray(data[pos + 1:pos + 1 + stride])
        pos += 1 + stride
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            pred = (0, a, b, (a + b) // 2, paeth(a, b, c))[kind] if kind <= 4 else None
            if pred is None:
                fail(f"unknown PNG filter {kind}")
            line[i] = (line[i] + pred) & 0xFF
        rows.append(bytes(line))
        prev = line
    return rows


def png(path, width, height):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail(f"{path}: not a PNG")
    pos, idat, ihdr = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    if not ihdr:
        fail(f"{path}: no IHDR")
    w, h, depth, colour = ihdr[:4]
    if (w, h) != (int(width), int(height)):
        fail(f"{path}: {w}x{h}, expected {width}x{height}")
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(colour)
    if depth != 8 or channels is None:
        fail(f"{path}: unexpected PNG depth {depth} / colour type {colour}")
    rows = png_rows(zlib.decompress(idat), w, h, channels)
    colours = {row[i:i + channels] for row in rows for i in range(0, len(row), channels)}
    if len(colours) < 2:
        fail(f"{path}: blank image (one colour)")


def svg(path, width, height):
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as e:
        fail(f"{path}: not well-formed XML: {e}")
    if root.tag != "{http://www.w3.org/2000/svg}svg":
        fail(f"{path}: root element is {root.tag}")
    if (root.get("width"), root.get("height")) != (width, height):
        fail(f"{path}: {root.get('width')}x{root.get('height')}, expected {width}x{height}")
    edges = [e for e in root.iter("{http://www.w3.org/2000/svg}path") if e.get("id") == "edges"]
    if not edges or not edges[0].get("d", "").strip():
        fail(f"{path}: no edges drawn")


def main(argv):
    cmds = {"same": (same, 2), "png": (png, 3), "svg": (svg, 3)}
    if len(argv) < 2 or argv[1] not in cmds or len(argv) - 2 != cmds[argv[1]][1]:
        fail("usage: views_check.py same|png|svg ARGS")
    cmds[argv[1]][0](*argv[2:])


if __name__ == "__main__":
    main(sys.argv)
