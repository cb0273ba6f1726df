#!/usr/bin/env python3
"""Extracts some countries from world-atlas's countries-110m.json (TopoJSON)
into a small GeoJSON fixture.

    npm pack world-atlas@2 && tar xzf world-atlas-2.0.2.tgz
    python3 make_countries.py package/countries-110m.json \\
        710,426,748,516,072,716,508,894,454,024,450,242,643,010,246,233,428,112,398,496 \\
        > countries_world.geojson

Each country keeps its ISO 3166-1 numeric code `id` and its `name`. The
decoding is make_counties.py's, so the borders two countries share stay
bit-identical. world-atlas stores Fiji, Russia and Antarctica stitched across
the antimeridian (segments from +180 to -180 and back), as TopoJSON does: the
fixture keeps them that way, for hpfc-pack to cut.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_counties import decode_arcs, geometry, write  # noqa: E402


def main():
    topo = json.load(open(sys.argv[1]))
    wanted = sys.argv[2].split(",")
    arcs = decode_arcs(topo)
    by_id = {g.get("id"): g for g in topo["objects"]["countries"]["geometries"]}
    feats = []
    for cid in wanted:
        g = by_id[cid]
        geom = geometry(g, arcs)
        if geom is None:
            continue
        feats.append({"type": "Feature", "id": cid,
                      "properties": {"id": cid, "name": g["properties"]["name"]},
                      "geometry": geom})
    write(feats)


main()
