#!/usr/bin/env python3
"""Extracts some states' counties from us-atlas's counties-10m.json (TopoJSON)
into a small GeoJSON fixture.

    npm pack us-atlas@3 && tar xzf us-atlas-3.0.1.tgz
    python3 make_counties.py package/counties-10m.json 44,10 > counties_ri_de.geojson

Decodes the TopoJSON arcs (quantised, delta-encoded) the way the
TopoJSON specification says, and writes each county as a (Multi)Polygon with
its FIPS code `id` and `name`. Coordinates are printed with the shortest
repr of the decoded doubles, so that the arcs two counties share stay
bit-identical in the output. make_countries.py uses the same decoding.
"""
import json
import sys


def decode_arcs(topo):
    """The arcs of a quantised topology as lists of [x, y] doubles."""
    sx, sy = topo["transform"]["scale"]
    tx, ty = topo["transform"]["translate"]
    arcs = []
    for arc in topo["arcs"]:
        x = y = 0
        pts = []
        for dx, dy in arc:
            x += dx
            y += dy
            pts.append([x * sx + tx, y * sy + ty])
        arcs.append(pts)
    return arcs


def geometry(g, arcs):
    """The GeoJSON geometry of a TopoJSON (Multi)Polygon, None for others."""
    def arc(i):
        return arcs[i] if i >= 0 else arcs[~i][::-1]

    def ring(ids):
        pts = []
        for i in ids:
            a = arc(i)
            pts.extend(a if not pts else a[1:])
        return pts

    if g["type"] == "Polygon":
        return {"type": "Polygon", "coordinates": [ring(r) for r in g["arcs"]]}
    if g["type"] == "MultiPolygon":
        return {"type": "MultiPolygon",
                "coordinates": [[ring(r) for r in p] for p in g["arcs"]]}
    return None


def write(feats):
    json.dump({"type": "FeatureCollection", "features": feats}, sys.stdout,
              separators=(",", ":"))
    sys.stdout.write("\n")


def main():
    topo = json.load(open(sys.argv[1]))
    prefixes = tuple(sys.argv[2].split(","))
    arcs = decode_arcs(topo)
    feats = []
    for g in topo["objects"]["counties"]["geometries"]:
        if not g["id"].startswith(prefixes):
            continue
        geom = geometry(g, arcs)
        if geom is None:
            continue
        feats.append({"type": "Feature", "id": g["id"],
                      "properties": {"fips": g["id"], "name": g["properties"]["name"]},
                      "geometry": geom})
    write(feats)


if __name__ == "__main__":
    main()
