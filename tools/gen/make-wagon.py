#!/usr/bin/env python3
"""Writes assets/models/wagon.gltf: a railway wagon made of boxes (glTF 2.0, embedded buffer).

glTF axes: +Y up, +Z the front, metres; the wheels stand on y = 0. Body 3.0 m wide, 18 m long;
three materials (body, roof, bogies) so that the model exercises materials and nodes: the bogies
are one mesh used by two nodes.
With --animated (the animated benchmark's wagon, tools/gen/bench-scenes.py): an animation "Run",
2 s long, in which the bogies swivel +-3 degrees (LINEAR rotations), the body and roof bob 3 cm
(CUBICSPLINE translation) and a pantograph on the roof, skinned to two joints, folds +-20
degrees at its elbow; every kind of channel and a skin, on a vehicle-sized rig.
Usage: make-wagon.py OUT.gltf [--animated]
"""
import base64, json, math, struct, sys

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

def main(out, animated=False):
    parts = {
        "body": [box(-1.5, 1.1, -9.0, 1.5, 3.7, 9.0)],
        "roof": [box(-1.4, 3.7, -8.8, 1.4, 4.1, 8.8)],
        "bogie": [box(-1.3, 0.0, -1.6, 1.3, 1.1, 1.6)],
    }
    if animated:
        parts["pantograph"] = [box(-0.1, 4.1, 2.9, 0.1, 5.6, 3.1)]
    blob = bytearray()
    views, accessors, meshes = [], [], {}

    def add(data, fmt, kind, comp, target=None):
        while len(blob) % 4:
            blob.append(0)
        start = len(blob)
        for v in data:
            blob.extend(struct.pack("<" + fmt, *(v if isinstance(v, tuple) else (v,))))
        view = {"buffer": 0, "byteOffset": start, "byteLength": len(blob) - start}
        if target:
            view["target"] = target
        views.append(view)
        acc = {"bufferView": len(views) - 1, "componentType": comp, "count": len(data), "type": kind}
        if kind == "SCALAR" and comp == 5126:
            acc["min"], acc["max"] = [min(data)], [max(data)]
        accessors.append(acc)
        return len(accessors) - 1
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
                                                       "indices": prims[2], "material": min(list(parts).index(name), 2)}]}
        if name == "pantograph":   # the roof end on joint 0, the top on joint 1
            attrs = meshes[name]["primitives"][0]["attributes"]
            attrs["JOINTS_0"] = add([(0 if p[1] < 5.0 else 1, 0, 0, 0) for p in pos], "4H", "VEC4", 5123, 34962)
            attrs["WEIGHTS_0"] = add([(1.0, 0.0, 0.0, 0.0) for p in pos], "4f", "VEC4", 5126, 34962)
    gltf = {
        "asset": {"version": "2.0", "generator": "orbis tools/gen/make-wagon.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "wagon", "children": [1, 2, 3, 4]},
                  {"name": "body", "mesh": 0}, {"name": "roof", "mesh": 1},
                  {"name": "front bogie", "mesh": 2, "translation": [0, 0, 6.0]},
                  {"name": "rear bogie", "mesh": 2, "translation": [0, 0, -6.0]}],
        "meshes": [meshes[name] for name in parts],
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
    if animated:
        animate(gltf, add)
        gltf["buffers"] = [{"byteLength": len(blob),
                            "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}]
    with open(out, "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")

def animate(gltf, add):
    """Adds the pantograph's skin and the "Run" animation (see the docstring)."""
    nodes = gltf["nodes"]
    nodes[0]["children"] = [1, 3, 4, 5, 6]
    nodes[1]["children"] = [2]                                     # the roof rides on the body
    nodes.append({"name": "pantograph", "mesh": 3, "skin": 0})     # 5: skinned: its transform is not used
    nodes.append({"name": "pantograph base", "translation": [0, 4.1, 3.0], "children": [7]})   # 6: joint 0
    nodes.append({"name": "pantograph elbow", "translation": [0, 1.5, 0]})                      # 7: joint 1
    ibm = []
    for y in (4.1, 5.6):   # inverse bind matrices: translations back from the joints (column-major)
        ibm.append((1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -y, -3.0, 1))
    gltf["skins"] = [{"name": "pantograph", "joints": [6, 7], "inverseBindMatrices": add(ibm, "16f", "MAT4", 5126)}]

    def quat(axis, deg):
        h = math.radians(deg) / 2
        return tuple(math.sin(h) * a for a in axis) + (math.cos(h),)
    times = [0.0, 0.5, 1.0, 1.5, 2.0]
    swivel = add([quat((0, 1, 0), a) for a in (0, 3, 0, -3, 0)], "4f", "VEC4", 5126)
    fold = add([quat((1, 0, 0), a) for a in (0, 20, 0, -20, 0)], "4f", "VEC4", 5126)
    # CUBICSPLINE: (in-tangent, value, out-tangent) per keyframe; flat tangents at the ends.
    bob = add([(0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0.03, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0)],
              "3f", "VEC3", 5126)
    t5, t3 = add(times, "f", "SCALAR", 5126), add([0.0, 1.0, 2.0], "f", "SCALAR", 5126)
    gltf["animations"] = [{
        "name": "Run",
        "samplers": [{"input": t5, "output": swivel}, {"input": t5, "output": fold},
                     {"input": t3, "output": bob, "interpolation": "CUBICSPLINE"}],
        "channels": [{"sampler": 0, "target": {"node": 3, "path": "rotation"}},
                     {"sampler": 0, "target": {"node": 4, "path": "rotation"}},
                     {"sampler": 1, "target": {"node": 7, "path": "rotation"}},
                     {"sampler": 2, "target": {"node": 1, "path": "translation"}}],
    }]

if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    main(args[0] if args else "wagon.gltf", "--animated" in sys.argv[1:])
