#!/usr/bin/python3
"""Convert a CityGML-derived OBJ (data/ingolstadt/bldg_4018215.obj) to CityJSON 1.1.

Writes the CityJSON test fixture tests/pipeline/fixtures/bldg_4018215.city.json
(standard library only):

    /usr/bin/python3 scripts/obj_to_cityjson.py \
        data/ingolstadt/bldg_4018215.obj tests/pipeline/fixtures/bldg_4018215.city.json

The OBJ's groups are named "<building id>/<CityGML class>/<object id>" and its
coordinates are EPSG:32632 minus (678000, 5403500, 400), Z up. The output:

* vertices quantised to millimetres (transform scale 0.001) with translate =
  the real-world origin (678000, 5403500, 400), so the file holds real UTM
  coordinates; metadata.referenceSystem is EPSG:32632;
* one CityObject per group: the Building group becomes the Building, every
  other group a child (parents/children links). CityJSON has no Window/Door
  city objects (they are semantic surfaces), so windows and doors become
  BuildingConstructiveElement objects whose surfaces carry the semantic type
  Window/Door; attributes.citygml_class keeps the source class;
* each object's geometry: a lod "3" MultiSurface, one triangle per surface
  (the OBJ is already triangulated; its triangles are kept one to one);
* the Building also gets a small lod "2" Solid: the axis-aligned box around
  its own lod 3 triangles, with Roof/Wall/Ground semantics. It is made up by
  this script (not in the source) so the loader's LOD choice can be tested.
"""
import json
import sys

OFFSET = (678000.0, 5403500.0, 400.0)
SCALE = 0.001


def read_obj(path):
    vertices, groups, order = [], {}, []
    current = None
    with open(path, encoding="utf-8") as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append(tuple(float(x) for x in parts[1:4]))
            elif parts[0] in ("g", "o"):
                current = " ".join(parts[1:])
                if current not in groups:
                    groups[current] = []
                    order.append(current)
            elif parts[0] == "f":
                if current is None:
                    raise SystemExit("face before any group")
                face = [int(c.split("/")[0]) for c in parts[1:]]
                face = [i - 1 if i > 0 else len(vertices) + i for i in face]
                if len(face) != 3:
                    raise SystemExit("expected a triangulated OBJ, got a %d-corner face" % len(face))
                groups[current].append(face)
    return vertices, groups, order


def quantise(v):
    # The OBJ's coordinates have three decimals: integers in millimetres are exact.
    return [round(v[a] / SCALE) for a in range(3)]


def main():
    if len(sys.argv) != 3:
        raise SystemExit("usage: obj_to_cityjson.py INPUT.obj OUTPUT.city.json")
    vertices, groups, order = read_obj(sys.argv[1])
    building_id, objects, children = None, {}, []
    for name in order:
        bid, cls, oid = name.split("/", 2)
        if cls == "Building":
            if building_id is not None:
                raise SystemExit("more than one Building group")
            building_id = oid
    if building_id is None:
        raise SystemExit("no Building group")

    for name in order:
        bid, cls, oid = name.split("/", 2)
        faces = groups[name]
        geometry = {"type": "MultiSurface", "lod": "3", "boundaries": [[f] for f in faces]}
        if cls in ("Window", "Door"):
            geometry["semantics"] = {"surfaces": [{"type": cls}], "values": [0] * len(faces)}
        obj = {"type": "Building" if cls == "Building" else
               "BuildingInstallation" if cls == "BuildingInstallation" else "BuildingConstructiveElement",
               "attributes": {"citygml_class": cls},
               "geometry": [geometry]}
        if cls != "Building":
            if bid != building_id:
                raise SystemExit("group %s names building %s, the file's building is %s" % (name, bid, building_id))
            obj["parents"] = [building_id]
            children.append(oid)
        if oid in objects:
            raise SystemExit("two groups for object %s" % oid)
        objects[oid] = obj

    out_vertices = [quantise(v) for v in vertices]

    # The made-up lod 2 block: the box around the Building's own triangles.
    used = {i for f in groups[next(n for n in order if n.split("/")[1] == "Building")] for i in f}
    lo = [min(out_vertices[i][a] for i in used) for a in range(3)]
    hi = [max(out_vertices[i][a] for i in used) for a in range(3)]
    base = len(out_vertices)
    for z in (lo[2], hi[2]):
        out_vertices += [[lo[0], lo[1], z], [hi[0], lo[1], z], [hi[0], hi[1], z], [lo[0], hi[1], z]]
    b = base
    shell = [[[b + 0, b + 3, b + 2, b + 1]],          # ground, facing down
             [[b + 4, b + 5, b + 6, b + 7]],          # roof, facing up
             [[b + 0, b + 1, b + 5, b + 4]], [[b + 1, b + 2, b + 6, b + 5]],
             [[b + 2, b + 3, b + 7, b + 6]], [[b + 3, b + 0, b + 4, b + 7]]]
    objects[building_id]["geometry"].append({
        "type": "Solid", "lod": "2", "boundaries": [shell],
        "semantics": {"surfaces": [{"type": "GroundSurface"}, {"type": "RoofSurface"}, {"type": "WallSurface"}],
                      "values": [[0, 1, 2, 2, 2, 2]]}})
    objects[building_id]["children"] = children

    city = {
        "type": "CityJSON",
        "version": "1.1",
        "transform": {"scale": [SCALE, SCALE, SCALE], "translate": list(OFFSET)},
        "metadata": {
            "title": "Ingolstadt LOD3 building 4018215 (converted from OBJ by scripts/obj_to_cityjson.py)",
            "referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/32632",
        },
        "CityObjects": objects,
        "vertices": out_vertices,
    }
    with open(sys.argv[2], "w", encoding="utf-8") as f:
        json.dump(city, f, separators=(",", ":"))
        f.write("\n")
    print("%d objects, %d vertices, %d triangles" %
          (len(objects), len(out_vertices), sum(len(g) for g in groups.values())))


if __name__ == "__main__":
    main()
