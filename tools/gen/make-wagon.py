#!/usr/bin/env python3
"""Writes assets/models/wagon.gltf: a railway wagon made of boxes (glTF 2.0, embedded buffer).

glTF axes: +Y up, +Z the front, metres; the wheels stand on y = 0. Body 3.0 m wide, 18 m long;
three materials (body, roof, bogies) so that the model exercises materials and nodes: the bogies
are one mesh used by two nodes.
Usage: make-wagon.py OUT.gltf
"""
import base64, json, struct, sys

def box(x0, y0, z0, x1, y1, z1):
    faces = [  # normal, four corners counter-clockwise seen from outside
        ((1, 0, 0), [(x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1)]),
        ((-1, 0, 0), [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)]),
        ((0, 1, 0), [(x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (x0, y1, z0)]),
        ((0, -1, 0), [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)]),
        ((0, 0, 1), [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]),
        ((0, 0, -1), [(x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0)]),
    ]
    pos, nrm, idx = [], [], []
    for n, quad in faces:
        base = len(pos)
        pos += quad
        nrm += [n] * 4
        idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return pos, nrm, idx

def main(out):
    parts = {
        "body": [box(-1.5, 1.1, -9.0, 1.5, 3.7, 9.0)],
        "roof": [box(-1.4, 3.7, -8.8, 1.4, 4.1, 8.8)],
        "bogie": [box(-1.3, 0.0, -1.6, 1.3, 1.1, 1.6)],
    }
    blob = bytearray()
    views, accessors, meshes = [], [], {}
    for name, boxes in parts.items():
        pos, nrm, idx = [], [], []
        for p, n, i in boxes:
            off = len(pos)
            pos += p; nrm += n; idx += [k + off for k in i]
        prims = []
        for data, fmt, target, kind, comp in ((pos, "3f", 34962, "VEC3", 5126), (nrm, "3f", 34962, "VEC3", 5126),
                                             (idx, "H", 34963, "SCALAR", 5123)):
            while len(blob) % 4:
                blob.append(0)
            start = len(blob)
            for v in data:
                blob += struct.pack("<" + fmt, *(v if isinstance(v, tuple) else (v,)))
            views.append({"buffer": 0, "byteOffset": start, "byteLength": len(blob) - start, "target": target})
            acc = {"bufferView": len(views) - 1, "componentType": comp, "count": len(data), "type": kind}
            if data is pos:
                acc["min"] = [min(p[k] for p in pos) for k in range(3)]
                acc["max"] = [max(p[k] for p in pos) for k in range(3)]
            accessors.append(acc)
            prims.append(len(accessors) - 1)
        meshes[name] = {"name": name, "primitives": [{"attributes": {"POSITION": prims[0], "NORMAL": prims[1]},
                                                       "indices": prims[2], "material": list(parts).index(name)}]}
    gltf = {
        "asset": {"version": "2.0", "generator": "orbis tools/gen/make-wagon.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "wagon", "children": [1, 2, 3, 4]},
                  {"name": "body", "mesh": 0}, {"name": "roof", "mesh": 1},
                  {"name": "front bogie", "mesh": 2, "translation": [0, 0, 6.0]},
                  {"name": "rear bogie", "mesh": 2, "translation": [0, 0, -6.0]}],
        "meshes": [meshes["body"], meshes["roof"], meshes["bogie"]],
        "materials": [
            {"name": "paint", "pbrMetallicRoughness": {"baseColorFactor": [0.62, 0.08, 0.06, 1.0]}},
            {"name": "roof", "pbrMetallicRoughness": {"baseColorFactor": [0.35, 0.36, 0.38, 1.0]}},
            {"name": "steel", "pbrMetallicRoughness": {"baseColorFactor": [0.08, 0.08, 0.09, 1.0]}},
        ],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }
    with open(out, "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")

if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "wagon.gltf")
