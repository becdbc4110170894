#!/usr/bin/env python3
"""Export one of our procedural .glb scenes as a Wavefront OBJ (+ MTL) for OpenSceneGraph, together
with the scene's camera and sun expressed in the OBJ's frame.

    glb2obj.py SCENE.glb OUT.obj [--camera NAME] [--light NAME] [--frame zup|sun-down]
                                 [--path OUT.path] [--json OUT.json] [--aspect W/H]

Standard library only (OSG 3.6 has no glTF reader; Debian's python3 has no trimesh). Handles
what pnb-make-scene writes: triangle primitives with POSITION (+ NORMAL), any index type, node
TRS/matrix hierarchies, perspective cameras, KHR_lights_punctual directional lights. Materials
become MTL colours only (Kd = Ka = baseColorFactor encoded to sRGB, because OSG's fixed-function
lighting writes its result straight to an 8-bit non-sRGB framebuffer; d = alpha; Ks = 0);
textures are ignored.

Frames. "glTF world" is the scene's own frame (Y up, metres): our player's frame. The OBJ is
written in a frame B = R * world and must be read with `-O noRotation` (otherwise OSG's OBJ
plugin rotates it by 90 degrees about X once more). Two choices of R:

  zup       R maps (x, y, z) -> (x, -z, y): B is Z up, what OSG's OBJ plugin would do itself.
  sun-down  R = (minimal rotation taking the Z-up sun direction to -Z) * zup: the sun travels
            straight down -Z in B. This is the frame bench-osgshadow uses, because osgshadow's
            light is only consistent for every technique when it points straight down (see
            bench/osgshadow/NOTES.md: ParallelSplitShadowMap reads Light::getDirection(), which
            osgshadow leaves at its default (0, 0, -1) under --noUpdate, while the lighting and
            ViewDependentShadowMap use the position (0, 0, 1, 0)). Rotating the scene instead
            of the light keeps the scene's own low sun, in the scene's own frame.

--path writes an osgGA::AnimationPathManipulator file (`osgshadow -p FILE`) holding the camera
as two identical control points ("time px py pz qx qy qz qw", OSG's quaternion order), so the
view is static. --json writes R, the camera (eye, centre, up, vertical fov, aspect, near, far)
and the sun in both frames, the bounds and the triangle count.
"""
import argparse
import json
import math
import struct
import sys

COMPONENT = {5120: ('b', 1), 5121: ('B', 1), 5122: ('h', 2), 5123: ('H', 2), 5125: ('I', 4),
             5126: ('f', 4)}
NCOMP = {'SCALAR': 1, 'VEC2': 2, 'VEC3': 3, 'VEC4': 4, 'MAT4': 16}


def load_glb(path):
    data = open(path, 'rb').read()
    magic, version, length = struct.unpack_from('<III', data, 0)
    if magic != 0x46546C67 or version != 2:
        sys.exit(f'glb2obj: {path}: not a glTF 2.0 binary (.glb)')
    pos, doc, binchunk = 12, None, b''
    while pos < length:
        clen, ctype = struct.unpack_from('<II', data, pos)
        chunk = data[pos + 8:pos + 8 + clen]
        if ctype == 0x4E4F534A:
            doc = json.loads(chunk)
        elif ctype == 0x004E4942:
            binchunk = chunk
        pos += 8 + clen
    if doc is None:
        sys.exit(f'glb2obj: {path}: no JSON chunk')
    if any('uri' in b for b in doc.get('buffers', [])):
        sys.exit(f'glb2obj: {path}: external buffers are not supported')
    return doc, binchunk


def read_accessor(doc, binchunk, index):
    acc = doc['accessors'][index]
    fmt, size = COMPONENT[acc['componentType']]
    n = NCOMP[acc['type']]
    count = acc['count']
    if 'bufferView' not in acc:
        return [tuple([0] * n)] * count if n > 1 else [0] * count
    view = doc['bufferViews'][acc['bufferView']]
    base = view.get('byteOffset', 0) + acc.get('byteOffset', 0)
    stride = view.get('byteStride', 0) or size * n
    if stride == size * n:
        flat = struct.unpack_from('<' + fmt * (n * count), binchunk, base)
        if n == 1:
            return list(flat)
        return [flat[i * n:(i + 1) * n] for i in range(count)]
    out = [struct.unpack_from('<' + fmt * n, binchunk, base + i * stride) for i in range(count)]
    return [o[0] for o in out] if n == 1 else out


# --- small linear algebra (4x4 as row-major lists, column-vector convention) -------------------
def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def quat_to_mat3(q):
    x, y, z, w = q
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def mat3_to_quat(m):
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        return ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, 0.25 * s)
    if m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2
        return (0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s)
    if m[1][1] > m[2][2]:
        s = math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2
        return ((m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s)
    s = math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2
    return ((m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s, (m[1][0] - m[0][1]) / s)


def node_matrix(node):
    if 'matrix' in node:
        m = node['matrix']  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    t = node.get('translation', [0, 0, 0])
    r = quat_to_mat3(node.get('rotation', [0, 0, 0, 1]))
    s = node.get('scale', [1, 1, 1])
    return [[r[i][0] * s[0], r[i][1] * s[1], r[i][2] * s[2], t[i]] for i in range(3)] + [[0, 0, 0, 1]]


def xform_point(m, p):
    return tuple(m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3] for i in range(3))


def xform_dir(m3, v):
    return tuple(m3[i][0] * v[0] + m3[i][1] * v[1] + m3[i][2] * v[2] for i in range(3))


def normal_matrix(m):
    a = [row[:3] for row in m[:3]]
    det = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
           - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
           + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))
    # inverse transpose = cofactor matrix / det
    cof = [[(a[(i + 1) % 3][(j + 1) % 3] * a[(i + 2) % 3][(j + 2) % 3]
             - a[(i + 1) % 3][(j + 2) % 3] * a[(i + 2) % 3][(j + 1) % 3]) / det
            for j in range(3)] for i in range(3)]
    return cof, det


def normalize(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v) if n > 0 else tuple(v)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def rotation_between(a, b):
    """Minimal rotation (3x3) taking unit vector a to unit vector b."""
    v = cross(a, b)
    c = dot(a, b)
    if c < -0.999999:  # opposite: rotate pi about any axis orthogonal to a
        axis = normalize(cross(a, (1, 0, 0) if abs(a[0]) < 0.9 else (0, 1, 0)))
        return [[2 * axis[i] * axis[j] - (1 if i == j else 0) for j in range(3)] for i in range(3)]
    k = 1.0 / (1.0 + c)
    vx = [[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]]
    vx2 = [[sum(vx[i][m] * vx[m][j] for m in range(3)) for j in range(3)] for i in range(3)]
    return [[(1 if i == j else 0) + vx[i][j] + vx2[i][j] * k for j in range(3)] for i in range(3)]


def mat3_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def srgb(c):
    c = min(max(c, 0.0), 1.0)
    return 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055


def r6(v):
    return [round(float(c), 6) + 0.0 for c in v]  # + 0.0: no negative zeros


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('glb')
    ap.add_argument('obj')
    ap.add_argument('--camera', help='camera node name (default: first camera node)')
    ap.add_argument('--light', help='directional light node name (default: first one)')
    ap.add_argument('--frame', choices=['zup', 'sun-down'], default='sun-down')
    ap.add_argument('--path', help='write an osgGA::AnimationPathManipulator file')
    ap.add_argument('--json', help='write camera/light/frame facts as JSON')
    ap.add_argument('--aspect', type=float, help='viewport aspect (default: the camera\'s)')
    args = ap.parse_args()

    doc, binchunk = load_glb(args.glb)
    nodes = doc.get('nodes', [])
    roots = doc['scenes'][doc.get('scene', 0)]['nodes']

    # World matrices of every node reachable from the scene.
    world = {}
    stack = [(i, [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) for i in roots]
    order = []
    while stack:
        i, parent = stack.pop()
        m = mat_mul(parent, node_matrix(nodes[i]))
        world[i] = m
        order.append(i)
        for c in reversed(nodes[i].get('children', [])):
            stack.append((c, m))
    order.sort()

    # Camera and sun in glTF world.
    cam_node = next((i for i in order if 'camera' in nodes[i]
                     and (args.camera is None or nodes[i].get('name') == args.camera)), None)
    if cam_node is None:
        sys.exit(f'glb2obj: no camera node{" named " + args.camera if args.camera else ""}')
    lights = doc.get('extensions', {}).get('KHR_lights_punctual', {}).get('lights', [])
    sun_node = next((i for i in order
                     if 'KHR_lights_punctual' in nodes[i].get('extensions', {})
                     and lights[nodes[i]['extensions']['KHR_lights_punctual']['light']]['type'] == 'directional'
                     and (args.light is None or nodes[i].get('name') == args.light)), None)
    if sun_node is None:
        sys.exit('glb2obj: no directional light node' + (f' named {args.light}' if args.light else ''))
    cm = world[cam_node]
    cm3 = [row[:3] for row in cm[:3]]
    eye_w = xform_point(cm, (0, 0, 0))
    fwd_w = normalize(xform_dir(cm3, (0, 0, -1)))
    up_w = normalize(xform_dir(cm3, (0, 1, 0)))
    persp = doc['cameras'][nodes[cam_node]['camera']].get('perspective')
    if persp is None:
        sys.exit('glb2obj: the camera is not perspective')
    sm = world[sun_node]
    sun_w = normalize(xform_dir([row[:3] for row in sm[:3]], (0, 0, -1)))  # travel direction

    # Output frame.
    zup = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]
    R = zup
    if args.frame == 'sun-down':
        R = mat3_mul(rotation_between(xform_dir(zup, sun_w), (0, 0, -1)), zup)
    R4 = [R[0] + [0], R[1] + [0], R[2] + [0], [0, 0, 0, 1]]

    # Geometry.
    out = open(args.obj, 'w')
    mtl_path = args.obj[:-4] + '.mtl' if args.obj.endswith('.obj') else args.obj + '.mtl'
    mtl_name = mtl_path.rsplit('/', 1)[-1]
    out.write(f'# {args.glb} exported by bench/osgshadow/glb2obj.py, frame {args.frame}; '
              'read with osgDB option noRotation\n')
    out.write(f'mtllib {mtl_name}\n')
    materials = doc.get('materials', [])
    used = set()
    vbase = nbase = 0
    tris = 0
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    for i in order:
        if 'mesh' not in nodes[i]:
            continue
        m = mat_mul(R4, world[i])
        nm, det = normal_matrix(m)
        flip = det < 0
        out.write(f'o {nodes[i].get("name", "node" + str(i))}\n')
        for prim in doc['meshes'][nodes[i]['mesh']]['primitives']:
            if prim.get('mode', 4) != 4:
                print(f'glb2obj: skipping a non-triangle primitive (mode {prim["mode"]}) of node {i}',
                      file=sys.stderr)
                continue
            pos = read_accessor(doc, binchunk, prim['attributes']['POSITION'])
            nor = (read_accessor(doc, binchunk, prim['attributes']['NORMAL'])
                   if 'NORMAL' in prim['attributes'] else None)
            idx = (read_accessor(doc, binchunk, prim['indices']) if 'indices' in prim
                   else list(range(len(pos))))
            mat = prim.get('material')
            mname = 'default' if mat is None else f'm{mat}'
            used.add(mat)
            out.write(f'usemtl {mname}\n')
            lines = []
            for p in pos:
                q = xform_point(m, p)
                for k in range(3):
                    lo[k] = min(lo[k], q[k])
                    hi[k] = max(hi[k], q[k])
                lines.append('v %.6g %.6g %.6g\n' % q)
            if nor is not None:
                for n in nor:
                    lines.append('vn %.6g %.6g %.6g\n' % normalize(xform_dir(nm, n)))
            out.write(''.join(lines))
            lines = []
            for t in range(0, len(idx) - 2, 3):
                a, b, c = idx[t] + 1 + vbase, idx[t + 1] + 1 + vbase, idx[t + 2] + 1 + vbase
                if flip:
                    b, c = c, b
                if nor is not None:
                    na, nb, nc = a - vbase + nbase, b - vbase + nbase, c - vbase + nbase
                    lines.append(f'f {a}//{na} {b}//{nb} {c}//{nc}\n')
                else:
                    lines.append(f'f {a} {b} {c}\n')
            out.write(''.join(lines))
            tris += len(idx) // 3
            vbase += len(pos)
            if nor is not None:
                nbase += len(nor)
    out.close()

    with open(mtl_path, 'w') as f:
        for mat in sorted(used, key=lambda x: -1 if x is None else x):
            if mat is None:
                f.write('newmtl default\nKa 0.8 0.8 0.8\nKd 0.8 0.8 0.8\nKs 0 0 0\nd 1\n\n')
                continue
            md = materials[mat]
            bc = md.get('pbrMetallicRoughness', {}).get('baseColorFactor', [1, 1, 1, 1])
            rgb = ' '.join('%.4f' % srgb(c) for c in bc[:3])
            alpha = bc[3] if md.get('alphaMode') == 'BLEND' else 1.0
            f.write(f'# {md.get("name", "")}\nnewmtl m{mat}\nKa {rgb}\nKd {rgb}\nKs 0 0 0\nd {alpha:.4f}\n\n')

    # Camera and sun in B.
    eye_b = xform_dir(R, eye_w)
    fwd_b = normalize(xform_dir(R, fwd_w))
    up_b = normalize(xform_dir(R, up_w))
    sun_b = normalize(xform_dir(R, sun_w))
    # OSG camera matrix (camera-to-world): local -Z = forward, +Y = up, +X = right.
    right = normalize(cross(fwd_b, up_b))
    up_o = cross(right, fwd_b)
    back = tuple(-c for c in fwd_b)
    rot = [[right[0], up_o[0], back[0]], [right[1], up_o[1], back[1]], [right[2], up_o[2], back[2]]]
    q = normalize(mat3_to_quat(rot))
    if args.path:
        with open(args.path, 'w') as f:
            for t in (0.0, 1000.0):
                f.write('%g %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n' % ((t,) + eye_b + q))

    yfov = math.degrees(persp['yfov'])
    aspect = args.aspect or persp.get('aspectRatio')
    elev = math.degrees(math.asin(-sun_w[1]))
    azim = math.degrees(math.atan2(-sun_w[2], sun_w[0]))
    facts = {
        'source': args.glb,
        'frame': args.frame,
        'R_world_to_obj': [r6(r) for r in R],
        'obj_read_option': 'noRotation',
        'triangles': tris,
        'bounds_obj': {'min': r6(lo), 'max': r6(hi)},
        'camera': {
            'node': nodes[cam_node].get('name'),
            'yfov_deg': round(yfov, 6),
            'aspect': aspect,
            'gltf_znear': persp.get('znear'), 'gltf_zfar': persp.get('zfar'),
            'world': {'eye': r6(eye_w), 'forward': r6(fwd_w), 'up': r6(up_w),
                      'center': r6(tuple(e + f for e, f in zip(eye_w, fwd_w)))},
            'obj': {'eye': r6(eye_b), 'forward': r6(fwd_b), 'up': r6(up_o),
                    'center': r6(tuple(e + f for e, f in zip(eye_b, fwd_b))),
                    'osg_path_quat_xyzw': r6(q)},
        },
        'sun': {
            'node': nodes[sun_node].get('name'),
            'world_travel_direction': r6(sun_w),
            'world_elevation_deg': round(elev, 4),
            'world_azimuth_deg_from_+x_towards_-z': round(azim, 4),
            'obj_travel_direction': r6(sun_b),
            'osg_light_position': r6(tuple(-c for c in sun_b)) + [0.0],
        },
    }
    if args.json:
        with open(args.json, 'w') as f:
            json.dump(facts, f, indent=2)
            f.write('\n')
    print(f'glb2obj: {args.obj}: {tris} triangles, camera {facts["camera"]["node"]}, '
          f'sun elevation {elev:.1f} deg, frame {args.frame}')


if __name__ == '__main__':
    main()
