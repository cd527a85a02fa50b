#!/usr/bin/env python3
"""Split a CityJSON district into N files of neighbouring buildings.

For batches run in shards (`perclod run CONFIG --shard i/n`, a Slurm array:
docs/usage.md#a-district-in-shards): a district is one model, and a shard
takes whole models, so a district becomes N models first. Each top-level
city object (a building, with its parts) goes to one file; the objects are
split at the median of their centres across the district's longer side,
again and again, so each file holds a compact patch of the district and
the files hold about the same number of buildings. Vertices are renumbered
per file; the transform and metadata are kept.

Usage: scripts/split_cityjson.py IN OUT_DIR --parts N
Writes OUT_DIR/<name>_part<k>of<N>.city.json (k = 1..N).
"""
import argparse
import json
import os
import sys


def family(objects, top):
    """`top` and every object below it, following "children"."""
    out, todo = [], [top]
    while todo:
        name = todo.pop()
        if name in objects and name not in out:
            out.append(name)
            todo.extend(objects[name].get("children", []))
    return out


def indices(boundaries):
    """Every vertex index in a geometry's nested boundaries."""
    if isinstance(boundaries, list):
        for b in boundaries:
            yield from indices(b)
    else:
        yield boundaries


def renumbered(boundaries, new):
    if isinstance(boundaries, list):
        return [renumbered(b, new) for b in boundaries]
    return new[boundaries]


def split(items, parts, out):
    """items: [(name, x, y)]; appends `parts` lists of names to out."""
    if parts == 1 or len(items) <= 1:
        out.append([n for n, _, _ in items])
        return
    xs = [x for _, x, _ in items]
    ys = [y for _, _, y in items]
    axis = 1 if max(xs) - min(xs) >= max(ys) - min(ys) else 2
    items = sorted(items, key=lambda i: (i[axis], i[0]))
    left = parts // 2
    cut = round(len(items) * left / parts)
    split(items[:cut], left, out)
    split(items[cut:], parts - left, out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("input")
    ap.add_argument("out_dir")
    ap.add_argument("--parts", type=int, required=True)
    a = ap.parse_args()
    try:
        with open(a.input) as f:
            city = json.load(f)
        objects, vertices = city["CityObjects"], city["vertices"]
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"split_cityjson.py: {a.input}: not a CityJSON file ({e})")
    tops = [n for n, o in objects.items() if not o.get("parents")]
    if not 1 <= a.parts <= len(tops):
        sys.exit(f"split_cityjson.py: --parts must be 1..{len(tops)} (the file's top-level objects), not {a.parts}")
    items, skipped = [], 0
    for n in tops:
        idx = [i for m in family(objects, n) for g in objects[m].get("geometry", []) for i in indices(g["boundaries"])]
        if not idx:
            skipped += 1  # no geometry: placed at the first vertex
            idx = [0]
        items.append((n, sum(vertices[i][0] for i in idx) / len(idx), sum(vertices[i][1] for i in idx) / len(idx)))
    groups = []
    split(items, a.parts, groups)
    stem = os.path.basename(a.input)
    for suffix in (".city.json", ".json"):
        if stem.endswith(suffix):
            stem = stem[: -len(suffix)]
            break
    os.makedirs(a.out_dir, exist_ok=True)
    for k, group in enumerate(groups, 1):
        names = [m for n in group for m in family(objects, n)]
        new, verts, objs = {}, [], {}
        for m in names:
            o = dict(objects[m])
            if "geometry" in o:
                for g in o["geometry"]:
                    for i in indices(g["boundaries"]):
                        if i not in new:
                            new[i] = len(verts)
                            verts.append(vertices[i])
                o["geometry"] = [dict(g, boundaries=renumbered(g["boundaries"], new)) for g in o["geometry"]]
            objs[m] = o
        part = dict(city, CityObjects=objs, vertices=verts)
        path = os.path.join(a.out_dir, f"{stem}_part{k}of{len(groups)}.city.json")
        with open(path + ".part", "w") as f:
            json.dump(part, f, separators=(",", ":"))
        os.replace(path + ".part", path)
        print(f"{path}: {len(group)} buildings, {len(verts)} vertices")
    if skipped:
        print(f"split_cityjson.py: {skipped} top-level objects without geometry", file=sys.stderr)


if __name__ == "__main__":
    main()
