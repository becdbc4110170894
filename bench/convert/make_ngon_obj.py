#!/usr/bin/env python3
"""bench_convert.sh's n-gon case: IN.obj with COUNT of its triangles made pentagons, as OUT.obj.

Why: Blender's OBJ exporter writes n-gons by default, and a held-out 1M-triangle OBJ with 75
pentagons among ~1M faces once sent the whole file to tinyobjloader (issue 38); the benchmark's
own OBJ (assimp's export) has only triangles. The file is generated at benchmark time, not
committed.

Each chosen triangle a b c (spread evenly over the faces) becomes the convex, planar pentagon
a b M c N, M and N the midpoints of b-c and c-a pushed outward from the triangle's centre by a
fifth of their distance to it; their uvs are placed the same way, their normals are c's. The new
positions and uvs are appended after the file's last "v" and "vt" lines, so no existing absolute
index changes (the chosen faces come after both); a file with relative (negative) indices is
refused. Other lines are copied byte for byte.
  make_ngon_obj.py IN.obj OUT.obj [COUNT]   (COUNT: 75)
"""
import sys


def main():
    src, dst = sys.argv[1], sys.argv[2]
    count = int(sys.argv[3]) if len(sys.argv) > 3 else 75
    lines = open(src, "rb").read().split(b"\n")
    last = {b"v": -1, b"vt": -1}
    v_lines, vt_lines = [], []
    faces = []
    for i, line in enumerate(lines):
        word = line.split(None, 1)[0] if line.strip() else b""
        if word == b"v":
            last[b"v"] = i
            v_lines.append(i)
        elif word == b"vt":
            last[b"vt"] = i
            vt_lines.append(i)
        elif word == b"f":
            if b" -" in line or b"/-" in line:
                sys.exit(f"make_ngon_obj: {src}: relative indices are not handled")
            faces.append(i)
    after = max(last.values())
    candidates = [i for i in faces if i > after and len(lines[i].split()) == 4]
    if len(candidates) < count:
        sys.exit(f"make_ngon_obj: {src}: {len(candidates)} triangles after the vertices, "
                 f"{count} wanted")

    def numbers(line_index, n):
        return [float(x) for x in lines[line_index].split()[1:1 + n]]

    def outward(p, q, centre):
        mid = [(a + b) / 2 for a, b in zip(p, q)]
        return [m + 0.2 * (m - c) for m, c in zip(mid, centre)]

    new_v, new_vt = [], []
    edits = {}
    step = len(candidates) / count
    for k in range(count):
        f = candidates[int(k * step)]
        corners = [c.split(b"/") for c in lines[f].split()[1:]]
        pos = [numbers(v_lines[int(c[0]) - 1], 3) for c in corners]
        centre = [sum(p[i] for p in pos) / 3 for i in range(3)]
        m = len(v_lines) + len(new_v) + 1
        new_v += [outward(pos[1], pos[2], centre), outward(pos[2], pos[0], centre)]
        has_vt = len(corners[0]) > 1 and corners[0][1] != b""
        tm = None
        if has_vt:
            uv = [numbers(vt_lines[int(c[1]) - 1], 2) for c in corners]
            uc = [sum(t[i] for t in uv) / 3 for i in range(2)]
            tm = len(vt_lines) + len(new_vt) + 1
            new_vt += [outward(uv[1], uv[2], uc), outward(uv[2], uv[0], uc)]

        def corner(v, t, n):
            parts = [str(v).encode()]
            if len(corners[0]) > 1:
                parts.append(str(t).encode() if t is not None else b"")
            if len(corners[0]) > 2:
                parts.append(n)
            return b"/".join(parts)

        cn = corners[2][2] if len(corners[2]) > 2 else b""
        a, b, c = corners
        edits[f] = b"f " + b" ".join([
            b"/".join(a), b"/".join(b),
            corner(m, tm, cn),
            b"/".join(c),
            corner(m + 1, tm + 1 if tm else None, cn),
        ]) + (b"\r" if lines[f].endswith(b"\r") else b"")

    with open(dst, "wb") as out:
        for i, line in enumerate(lines):
            out.write(edits.get(i, line))
            if i + 1 < len(lines):
                out.write(b"\n")
            if i == last[b"v"]:
                out.writelines(b"v %.6g %.6g %.6g\n" % tuple(p) for p in new_v)
            if i == last[b"vt"]:
                out.writelines(b"vt %.6g %.6g\n" % tuple(t) for t in new_vt)
    print(f"make_ngon_obj: {dst}: {count} pentagons among {len(faces)} faces")


if __name__ == "__main__":
    main()
