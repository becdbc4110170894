"""The view a conformance render uses, computed from the glTF file itself (stdlib only).

The harness does not rely on pnb-convert's default camera: that framing is being changed (issue
38, item 3), and a criterion must not pass or fail with it. Instead it reads the scene's bounds
from the file (each mesh's POSITION accessor min/max through the node transforms, instances of
EXT_mesh_gpu_instancing included) and writes a two-key camera path (pnb-play --path FILE) that
looks at the bounds' centre from a chosen direction, every corner inside the frustum with a
margin: what the sample viewer does when it opens a model.
"""

import json
import math
import struct


def load_gltf_json(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"glTF":
        (length, kind) = struct.unpack("<I4s", data[12:20])
        if kind != b"JSON":
            raise ValueError(f"{path}: first GLB chunk is not JSON")
        return json.loads(data[20:20 + length])
    return json.loads(data)


def _mat_mul(a, b):
    # 4x4, column-major lists of 16 like glTF's node.matrix.
    return [sum(a[k * 4 + r] * b[c * 4 + k] for k in range(4)) for c in range(4) for r in range(4)]


def _trs(node):
    if "matrix" in node:
        return list(node["matrix"])
    tx, ty, tz = node.get("translation", [0, 0, 0])
    qx, qy, qz, qw = node.get("rotation", [0, 0, 0, 1])
    sx, sy, sz = node.get("scale", [1, 1, 1])
    r = [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy + qz * qw), 2 * (qx * qz - qy * qw),
         2 * (qx * qy - qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + qx * qw),
         2 * (qx * qz + qy * qw), 2 * (qy * qz - qx * qw), 1 - 2 * (qx * qx + qy * qy)]
    return [r[0] * sx, r[1] * sx, r[2] * sx, 0, r[3] * sy, r[4] * sy, r[5] * sy, 0,
            r[6] * sz, r[7] * sz, r[8] * sz, 0, tx, ty, tz, 1]


def _apply(m, p):
    return [m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r] for r in range(3)]


def _box_corners(lo, hi):
    return [[(lo, hi)[i & 1][0], (lo, hi)[(i >> 1) & 1][1], (lo, hi)[(i >> 2) & 1][2]]
            for i in range(8)]


def scene_points(doc):
    """Corners of every mesh's POSITION box in world space (the default scene's nodes)."""
    scenes = doc.get("scenes", [])
    roots = scenes[doc.get("scene", 0)]["nodes"] if scenes else range(len(doc.get("nodes", [])))
    nodes, meshes, accessors = doc.get("nodes", []), doc.get("meshes", []), doc.get("accessors", [])
    points = []

    def visit(i, parent):
        node = nodes[i]
        world = _mat_mul(parent, _trs(node))
        if "mesh" in node:
            inst = node.get("extensions", {}).get("EXT_mesh_gpu_instancing", {}).get("attributes", {})
            offsets = [[0, 0, 0]]
            if "TRANSLATION" in inst and "min" in accessors[inst["TRANSLATION"]]:
                a = accessors[inst["TRANSLATION"]]
                offsets = _box_corners(a["min"], a["max"])
            grow = 1.0
            if "SCALE" in inst and "max" in accessors[inst["SCALE"]]:
                grow = max(abs(v) for v in accessors[inst["SCALE"]]["max"]) * math.sqrt(3)
            for prim in meshes[node["mesh"]].get("primitives", []):
                a = accessors[prim["attributes"]["POSITION"]]
                if "min" not in a:
                    continue
                for c in _box_corners(a["min"], a["max"]):
                    for o in offsets:
                        local = [c[k] * grow + o[k] for k in range(3)] if len(offsets) > 1 else c
                        points.append(_apply(world, local))
        for child in node.get("children", []):
            visit(child, world)

    identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
    for r in roots:
        visit(r, identity)
    return points


def _normalize(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def camera_path(gltf_path, direction=(0, 0, 1), yfov_degrees=40.0, margin=1.12, aspect=4 / 3):
    """A still two-key path (pnb-play --path) looking at the scene's bounds along -direction.

    The eye is as close as it can be with every corner of every mesh box inside the frustum,
    `margin` times the tightest fit (the box's projection, not its bounding sphere: a flat test
    board then fills the frame as in the sample viewer).
    """
    points = scene_points(load_gltf_json(gltf_path))
    lo = [min(p[k] for p in points) for k in range(3)]
    hi = [max(p[k] for p in points) for k in range(3)]
    centre = [(lo[k] + hi[k]) / 2 for k in range(3)]
    back = _normalize(direction)                 # from the centre towards the eye
    up = [0, 1, 0] if abs(back[1]) < 0.99 else [0, 0, -1]
    right = _normalize(_cross(up, back))
    up = _cross(back, right)
    tan_v = math.tan(math.radians(yfov_degrees) / 2)
    tan_h = tan_v * aspect
    distance = 0.0
    for p in points:
        d = [p[k] - centre[k] for k in range(3)]
        x = sum(d[k] * right[k] for k in range(3))
        y = sum(d[k] * up[k] for k in range(3))
        z = sum(d[k] * back[k] for k in range(3))
        distance = max(distance, z + margin * abs(x) / tan_h, z + margin * abs(y) / tan_v)
    eye = [centre[k] + back[k] * distance for k in range(3)]
    key = {"position": eye, "target": centre, "yfov_degrees": yfov_degrees}
    return {"name": "conformance", "interpolation": "linear", "loop": False,
            "keys": [dict(key, time=0), dict(key, time=1)]}
