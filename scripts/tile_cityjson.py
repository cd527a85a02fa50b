#!/usr/bin/env python3
"""Write a larger district made of copies of a CityJSON file side by side.

For the district-size benchmark (BENCHMARKS.md#a-district-of-many-copies):
NX x NY copies of the input's city objects on a grid whose step is the
input's extent plus a gap, so the copies read as one town. Copy (0, 0)
keeps the input's ids; copy (i, j) appends "-c<i>x<j>" to every id (and to
the parents and children it names). Only vertex indices move: semantics,
attributes and the transform stay as they are.

Usage: scripts/tile_cityjson.py IN OUT --copies NX NY [--gap METRES]
"""
import argparse
import json
import os
import sys


def shifted(boundaries, by):
    """The nested vertex indices of a geometry's boundaries, plus `by`."""
    if isinstance(boundaries, list):
        return [shifted(b, by) for b in boundaries]
    return boundaries + by


def extent(vertices, transform):
    """[minx, miny, maxx, maxy] of the vertices in real coordinates."""
    s, t = transform["scale"], transform["translate"]
    xs = [v[0] for v in vertices]
    ys = [v[1] for v in vertices]
    return [min(xs) * s[0] + t[0], min(ys) * s[1] + t[1], max(xs) * s[0] + t[0], max(ys) * s[1] + t[1]]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--copies", nargs=2, type=int, required=True, metavar=("NX", "NY"))
    ap.add_argument("--gap", type=float, default=20.0, help="metres between copies (default 20)")
    a = ap.parse_args()
    if a.copies[0] < 1 or a.copies[1] < 1:
        sys.exit("tile_cityjson.py: --copies takes two numbers of at least 1")
    try:
        with open(a.input) as f:
            city = json.load(f)
        transform = city["transform"]
        vertices = city["vertices"]
        objects = city["CityObjects"]
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"tile_cityjson.py: {a.input}: not a CityJSON file with a transform ({e})")
    box = extent(vertices, transform)
    step = [(box[2] - box[0] + a.gap) / transform["scale"][0], (box[3] - box[1] + a.gap) / transform["scale"][1]]
    nv = len(vertices)
    out_vertices, out_objects = [], {}
    for j in range(a.copies[1]):
        for i in range(a.copies[0]):
            k = j * a.copies[0] + i
            dx, dy = round(i * step[0]), round(j * step[1])
            out_vertices.extend([v[0] + dx, v[1] + dy, v[2]] for v in vertices)
            rename = (lambda n: n) if k == 0 else (lambda n, s=f"-c{i}x{j}": n + s)
            for name, obj in objects.items():
                o = dict(obj)
                if "geometry" in o:
                    o["geometry"] = [dict(g, boundaries=shifted(g["boundaries"], k * nv)) for g in o["geometry"]]
                for key in ("parents", "children"):
                    if key in o:
                        o[key] = [rename(n) for n in o[key]]
                out_objects[rename(name)] = o
    city["vertices"] = out_vertices
    city["CityObjects"] = out_objects
    meta = city.get("metadata")
    if isinstance(meta, dict) and "geographicalExtent" in meta:
        e = meta["geographicalExtent"]
        s = transform["scale"]
        e[3] = e[0] + (e[3] - e[0]) + (a.copies[0] - 1) * step[0] * s[0]
        e[4] = e[1] + (e[4] - e[1]) + (a.copies[1] - 1) * step[1] * s[1]
    with open(a.output + ".part", "w") as f:
        json.dump(city, f, separators=(",", ":"))
    os.replace(a.output + ".part", a.output)
    buildings = sum(1 for o in out_objects.values() if o.get("type") == "Building")
    print(f"{a.output}: {a.copies[0]} x {a.copies[1]} copies, {buildings} buildings, {len(out_vertices)} vertices")


if __name__ == "__main__":
    main()
