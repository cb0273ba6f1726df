#!/usr/bin/env python3
"""File sizes with exact geometry: bytes per shape point of a
packed .hpfc (whole file, and its GEOM section alone) against FlatGeobuf,
GeoPackage (both by ogr2ogr, attributes kept) and quantized TopoJSON (the
layer's object alone, with only the arcs it uses, as the npm packages ship
it), for us-atlas counties-10m and world-atlas countries-10m.

    python3 bench/geom_sizes.py [HPFC_PACK] [NODE_MODULES] [WORKDIR]

Defaults: build-bench/hpfc-pack/hpfc-pack (built by bench/run.sh; any build
gives the same bytes), /tmp/gis/node_modules (`npm install us-atlas
world-atlas` there), build-bench/geom. Prints a Markdown table.

A shape point is a vertex of a ring as the GeoJSON of the layer lists it
(ogr2ogr -f GeoJSON), closing vertex included: what FlatGeobuf stores, 16
bytes each. Shared borders count once per ring that runs along them; the
hpfc file and TopoJSON store them once.
"""
import json
import os
import struct
import subprocess
import sys

# hpfc-pack's defaults (--vertices junctions --leaf-points 16), the same
# without the leaf bound, and a vertex at every shape point.
CONFIGS = [
    ("defaults", []),
    ("`--leaf-points 0`", ["--leaf-points", "0"]),
    ("`--vertices all`", ["--vertices", "all"]),
]

LAYERS = [
    ("us-atlas counties-10m", "us-atlas/counties-10m.json", "counties"),
    ("world-atlas countries-10m", "world-atlas/countries-10m.json", "countries"),
]


def run(*cmd):
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def count_points(geojson_path):
    """Ring vertices of every polygon feature (closing vertices included)."""
    with open(geojson_path) as f:
        data = json.load(f)
    total = 0
    for feat in data["features"]:
        g = feat.get("geometry")
        if not g:
            continue
        polys = g["coordinates"] if g["type"] == "MultiPolygon" else [g["coordinates"]]
        for poly in polys:
            for ring in poly:
                total += len(ring)
    return total, len(data["features"])


def topojson_one_object(src, name, out):
    """The object `name` of a TopoJSON topology with only its own arcs,
    renumbered, written compactly (what `topojson` tools would ship)."""
    with open(src) as f:
        topo = json.load(f)
    obj = topo["objects"][name]
    used = {}

    def arc_ids(arcs):
        for a in arcs:
            if isinstance(a, list):
                arc_ids(a)
            else:
                used.setdefault(a if a >= 0 else ~a, None)

    for g in obj["geometries"]:
        if "arcs" in g:
            arc_ids(g["arcs"])
    order = sorted(used)
    index = {a: k for k, a in enumerate(order)}

    def renumber(arcs):
        return [renumber(a) if isinstance(a, list) else (index[a] if a >= 0 else ~index[~a]) for a in arcs]

    for g in obj["geometries"]:
        if "arcs" in g:
            g["arcs"] = renumber(g["arcs"])
    small = {"type": "Topology", "objects": {name: obj}, "arcs": [topo["arcs"][a] for a in order]}
    if "transform" in topo:
        small["transform"] = topo["transform"]
    if "bbox" in topo:
        small["bbox"] = topo["bbox"]
    with open(out, "w") as f:
        json.dump(small, f, separators=(",", ":"))
    return os.path.getsize(out)


def sections(path):
    """{tag: (offset, length)} from the file's section directory (spec §4.4)."""
    with open(path, "rb") as f:
        data = f.read()
    header_size = struct.unpack_from("<I", data, 12)[0]
    levels = struct.unpack_from("<I", data, 40)[0]
    count = struct.unpack_from("<I", data, 44)[0]
    at = header_size + 64 * levels
    out = {}
    for k in range(count):
        e = at + 32 * k
        tag = data[e:e + 4].decode()
        off, length = struct.unpack_from("<QQ", data, e + 8)
        out[tag] = (off, length)
    return data, out


def geom_counts(data, secs):
    off, _ = secs["GEOM"]
    return struct.unpack_from("<QQQ", data, off)


def main():
    pack = sys.argv[1] if len(sys.argv) > 1 else "build-bench/hpfc-pack/hpfc-pack"
    modules = sys.argv[2] if len(sys.argv) > 2 else "/tmp/gis/node_modules"
    work = sys.argv[3] if len(sys.argv) > 3 else "build-bench/geom"
    os.makedirs(work, exist_ok=True)
    rows = []
    for title, rel, layer in LAYERS:
        src = os.path.join(modules, rel)
        base = os.path.join(work, layer)
        for ext in ("geojson", "fgb", "gpkg"):
            if os.path.exists(f"{base}.{ext}"):
                os.remove(f"{base}.{ext}")
        run("ogr2ogr", "-f", "GeoJSON", f"{base}.geojson", src, layer)
        run("ogr2ogr", "-f", "FlatGeobuf", f"{base}.fgb", src, layer)
        run("ogr2ogr", "-f", "GPKG", f"{base}.gpkg", src, layer)
        points, features = count_points(f"{base}.geojson")
        sizes = {
            "FlatGeobuf": os.path.getsize(f"{base}.fgb"),
            "GeoPackage": os.path.getsize(f"{base}.gpkg"),
            "TopoJSON (quantized, this object)": topojson_one_object(src, layer, f"{base}.topo.json"),
        }
        hpfc = {}
        for model, options in CONFIGS:
            out = f"{base}.{len(hpfc)}.hpfc"
            run(pack, src, "-l", layer, "--fields", "all", *options, "-o", out, "--force", "-q")
            data, secs = sections(out)
            v, e, p = geom_counts(data, secs)
            hpfc[model] = (len(data), secs["GEOM"][1], v, e, p)
        rows.append((title, features, points, sizes, hpfc))
    print("| layer | shape points | format | bytes | bytes per shape point |")
    print("|---|---|---|---|---|")
    for title, features, points, sizes, hpfc in rows:
        head = f"{title} ({features} features)"
        first = True
        for name, size in sizes.items():
            print(f"| {head if first else ''} | {points if first else ''} | {name} | {size:,} | "
                  f"{size / points:.2f} |")
            first = False
        for model, (size, geom, v, e, p) in hpfc.items():
            print(f"| | | hpfc {model} `--fields all`, whole file | {size:,} | "
                  f"{size / points:.2f} |")
            print(f"| | | its GEOM section ({v:,} vertices, {e:,} edges, {p:,} shape points: "
                  f"{8 * geom / (v + p):.1f} bits per stored point) | {geom:,} | "
                  f"{geom / points:.2f} |")


if __name__ == "__main__":
    main()
