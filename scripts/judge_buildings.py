#!/usr/bin/env python3
"""Judge a district's LODs building by building, each building alone.

For a sample of buildings of a CityJSON district, cuts each building out of
the original file and out of every LOD set given (OBJ files written by
`perclod run`, whose groups are named "<building>/..."), and judges each
cut LOD against the cut original with `perclod judge` from the held-out
views framed on that building alone, at the LOD's distance. Prints one row
per building and LOD set, and a summary: the worst visible ratio, how many
buildings are within the limit, and each building's triangles against the
first set's.

  scripts/judge_buildings.py CITY.json --up z --count 50 --seed 1 \\
      --lods alone=out_a/delft/delft_lod_{d}m.obj groups=out_b/delft/delft_lod_{d}m.obj \\
      --distances 56,132,427 [--perclod build/perclod] [--work /tmp/judge] [--json out.json]
"""
import argparse
import json
import os
import random
import statistics
import subprocess
import sys


def cut_cityjson(city, building, path):
    """The building and its parts as a CityJSON file of their own."""
    objects = city["CityObjects"]
    keep = {building, *objects[building].get("children", [])}
    out = dict(city)
    out["CityObjects"] = {k: v for k, v in objects.items() if k in keep}
    with open(path, "w") as f:
        json.dump(out, f)


def read_obj(path):
    """Vertex lines and, per building (the text of a group name before '/'),
    its face lines with the material in force."""
    vertices, faces, mtllib = [], {}, None
    group, material = None, None
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append(line)
            elif line.startswith("g "):
                group = line[2:].strip().split("/")[0]
            elif line.startswith("usemtl "):
                material = line
            elif line.startswith("f "):
                faces.setdefault(group, []).append((material, line))
            elif line.startswith("mtllib "):
                mtllib = os.path.join(os.path.dirname(os.path.abspath(path)), line[7:].strip())
    return vertices, faces, mtllib


def cut_obj(obj, building, path):
    """The building's faces of an OBJ read by read_obj, on their own vertices;
    returns how many triangles."""
    vertices, faces, mtllib = obj
    index, lines, triangles, material = {}, [], 0, None
    for mat, face in faces.get(building, []):
        if mat != material and mat:
            lines.append(mat)
            material = mat
        refs = []
        for r in face.split()[1:]:
            v = int(r.split("/")[0])
            v = v - 1 if v > 0 else len(vertices) + v
            if v not in index:
                index[v] = len(index) + 1
            refs.append(str(index[v]))
        lines.append("f " + " ".join(refs) + "\n")
        triangles += len(refs) - 2
    with open(path, "w") as f:
        if mtllib:
            f.write("mtllib %s\n" % mtllib)
        for v in sorted(index, key=index.get):
            f.write(vertices[v])
        f.write("g %s\n" % building)
        f.writelines(lines)
    return triangles


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("city")
    ap.add_argument("--lods", nargs="+", required=True, help="NAME=PATTERN with {d} for the distance")
    ap.add_argument("--distances", default="56,132,427")
    ap.add_argument("--up", default="z")
    ap.add_argument("--count", type=int, default=50)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--perclod", default=os.path.join(os.path.dirname(__file__), "..", "build", "perclod"))
    ap.add_argument("--work", default="/tmp/perclod_judge_buildings")
    ap.add_argument("--json", help="write every row here")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    with open(a.city) as f:
        city = json.load(f)
    buildings = sorted(k for k, v in city["CityObjects"].items() if v["type"] == "Building")
    sample = sorted(random.Random(a.seed).sample(buildings, min(a.count, len(buildings))))
    sets = [s.split("=", 1) for s in a.lods]
    distances = [float(d) for d in a.distances.split(",")]
    rows = []
    for d in distances:
        tag = "%g" % d
        objs = {name: read_obj(pattern.format(d=tag)) for name, pattern in sets}
        for i, b in enumerate(sample):
            original = os.path.join(a.work, "original_%d.city.json" % i)
            if not os.path.exists(original):
                cut_cityjson(city, b, original)
            for name, _ in sets:
                lod = os.path.join(a.work, "%s_%s_%d.obj" % (name, tag, i))
                triangles = cut_obj(objs[name], b, lod)
                r = subprocess.run([a.perclod, "judge", original, lod, "--up", a.up, "-d", tag, "--json"],
                                   capture_output=True, text=True)
                if r.returncode != 0:
                    sys.exit("perclod judge failed on %s (%s at %s m):\n%s" % (b, name, tag, r.stderr))
                worst = json.loads(r.stdout)["distances"][0]["fidelity"]["worst"]
                row = {"building": b, "set": name, "distance": d, "triangles": triangles,
                       "visible_ratio": worst["visible_ratio"], "visible_local_ratio": worst["visible_local_ratio"]}
                rows.append(row)
                print("%6g m %-8s %-36s %6d triangles, visible %.3fx, local %.3fx" %
                      (d, name, b, triangles, row["visible_ratio"], row["visible_local_ratio"]), flush=True)
    print("\nsummary (%d buildings, seed %d)" % (len(sample), a.seed))
    first = sets[0][0]
    for d in distances:
        base = {r["building"]: r["triangles"] for r in rows if r["distance"] == d and r["set"] == first}
        for name, _ in sets:
            rs = [r for r in rows if r["distance"] == d and r["set"] == name]
            vis = [r["visible_ratio"] for r in rs]
            rel = [r["triangles"] / base[r["building"]] - 1 for r in rs if base[r["building"]] > 0]
            print("%6g m %-8s triangles %7d, visible: median %.3fx, worst %.3fx, within 1x: %d/%d; "
                  "triangles against %s: median %+.1f%%, within 5%%: %d/%d" %
                  (d, name, sum(r["triangles"] for r in rs), statistics.median(vis), max(vis),
                   sum(v <= 1 for v in vis), len(vis), first, 100 * statistics.median(rel),
                   sum(abs(x) <= 0.05 for x in rel), len(rel)))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
