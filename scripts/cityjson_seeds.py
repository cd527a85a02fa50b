#!/usr/bin/env python3
"""Write the CityJSON fuzz seeds (tests/fuzz/corpus/fuzz_cityjson/).

Small cuts of real files, so each mutation parses in well under a
millisecond: buildings of the Delft 3D BAG tile (../shared/data/cityjson,
CityJSON 1.0 with a transform, LoD 0 footprints and LoD 1.2/1.3/2.2 solids
with semantics) and of the converted demo building
(tests/pipeline/fixtures/bldg_4018215.city.json, 1.1, LoD 2 and 3), their
vertices renumbered; the geometry types the real files lack (templates,
holes, materials, MultiSolid) written out; and issue 56's crash, a vertex
nested 100,000 arrays deep.

Usage: scripts/cityjson_seeds.py [OUT_DIR]
"""
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DELFT = os.path.join(ROOT, "..", "shared", "data", "cityjson", "3dbag_5910_delft.city.json")
FIXTURE = os.path.join(ROOT, "tests", "pipeline", "fixtures", "bldg_4018215.city.json")


def renumber(boundaries, old_vertices, new_vertices, index):
    """The boundaries with each vertex index replaced by its new one."""
    if isinstance(boundaries, list):
        return [renumber(b, old_vertices, new_vertices, index) for b in boundaries]
    if boundaries not in index:
        index[boundaries] = len(new_vertices)
        new_vertices.append(old_vertices[boundaries])
    return index[boundaries]


def cut(doc, top_ids, keep_children=1000):
    """A document of the top-level objects top_ids, their children, and only their vertices."""
    objects, vertices, index = {}, [], {}
    for top in top_ids:
        ids = [top] + doc["CityObjects"][top].get("children", [])[:keep_children]
        for oid in ids:
            obj = json.loads(json.dumps(doc["CityObjects"][oid]))
            if "children" in obj:
                obj["children"] = [c for c in obj["children"] if c in ids]
            for g in obj.get("geometry", []):
                g["boundaries"] = renumber(g["boundaries"], doc["vertices"], vertices, index)
            obj.pop("attributes", None)
            objects[oid] = obj
    out = {"type": "CityJSON", "version": doc["version"]}
    if "transform" in doc:
        out["transform"] = doc["transform"]
    out["CityObjects"] = objects
    out["vertices"] = vertices
    return out


def tops(doc):
    return [k for k, o in doc["CityObjects"].items() if not o.get("parents")]


HANDWRITTEN = {
    # A template placed twice, materials with a default theme, a hole.
    "templates_materials_hole.city.json": {
        "type": "CityJSON", "version": "2.0",
        "transform": {"scale": [0.01, 0.01, 0.01], "translate": [1000, 2000, 0]},
        "appearance": {"materials": [{"name": "red", "diffuseColor": [1, 0, 0]}, {"name": "glass"}],
                       "default-theme-material": "look"},
        "geometry-templates": {"templates": [{"type": "MultiSurface", "lod": "2", "boundaries": [[[0, 1, 2]]]}],
                               "vertices-templates": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]},
        "CityObjects": {
            "B": {"type": "Building", "geometry": [{
                "type": "MultiSurface", "lod": "2",
                "boundaries": [[[0, 1, 2, 3], [7, 6, 5, 4]]],
                "material": {"look": {"values": [0]}, "other": {"value": 1}}}]},
            "T": {"type": "SolitaryVegetationObject", "geometry": [
                {"type": "GeometryInstance", "template": 0, "boundaries": [8],
                 "transformationMatrix": [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1]},
                {"type": "GeometryInstance", "template": 0, "boundaries": [0],
                 "transformationMatrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}]}},
        "vertices": [[0, 0, 0], [1000, 0, 0], [1000, 1000, 0], [0, 1000, 0],
                     [200, 200, 0], [400, 200, 0], [400, 400, 0], [200, 400, 0], [5000, 0, 0]]},
    # A MultiSolid and a CompositeSolid of parts, semantics, a LoD 1 and 2.2.
    "multisolid_parts.city.json": {
        "type": "CityJSON", "version": "1.1",
        "CityObjects": {
            "B": {"type": "Building", "children": ["P"], "geometry": [
                {"type": "MultiSolid", "lod": "2.2", "boundaries": [[[[0, 3, 2, 1]], [[4, 5, 6, 7]], [[0, 1, 5, 4]],
                                                                     [[1, 2, 6, 5]], [[2, 3, 7, 6]], [[3, 0, 4, 7]]]],
                 "semantics": {"surfaces": [{"type": "GroundSurface"}, {"type": "RoofSurface"},
                                            {"type": "WallSurface"}], "values": [[[0, 1, 2, 2, 2, 2]]]}},
                {"type": "MultiSurface", "lod": 1, "boundaries": [[[0, 3, 2, 1]]]}]},
            "P": {"type": "BuildingPart", "parents": ["B"], "geometry": [
                {"type": "CompositeSolid", "lod": "2.2", "boundaries": [[[[4, 5, 6, 7]], [[0, 1, 5, 4]]]]}]}},
        "vertices": [[0, 0, 0], [4, 0, 0], [4, 3, 0], [0, 3, 0], [0, 0, 5], [4, 0, 5], [4, 3, 5], [0, 3, 5]]},
}


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "tests", "fuzz", "corpus", "fuzz_cityjson")
    os.makedirs(out_dir, exist_ok=True)
    seeds = {}
    delft = json.load(open(DELFT, encoding="utf-8"))
    t = tops(delft)
    seeds["delft_1_building.city.json"] = cut(delft, t[:1])
    seeds["delft_3_buildings.city.json"] = cut(delft, t[100:103])
    fixture = json.load(open(FIXTURE, encoding="utf-8"))
    seeds["ingolstadt_parts.city.json"] = cut(fixture, tops(fixture), keep_children=2)
    seeds.update(HANDWRITTEN)
    for name, doc in seeds.items():
        with open(os.path.join(out_dir, name), "w", encoding="utf-8") as f:
            json.dump(doc, f, separators=(",", ":"))
            f.write("\n")
    # Issue 56, item 1: rendering this vertex in the error overflowed the stack.
    deep = '{"type":"CityJSON","version":"2.0","CityObjects":{},"vertices":[' + "[" * 100000 + "]" * 100000 + "]}\n"
    with open(os.path.join(out_dir, "crash_deep_vertex.city.json"), "w", encoding="utf-8") as f:
        f.write(deep)
    for name in sorted(os.listdir(out_dir)):
        print("%8d  %s" % (os.path.getsize(os.path.join(out_dir, name)), name))


if __name__ == "__main__":
    main()
