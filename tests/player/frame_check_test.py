#!/usr/bin/env python3
"""No silent wrong frames (issue 41, items 3 and 4).

- A source light far brighter than a renderer can add up (intensity 3e38: before the bound,
  FLT_MAX-sized lights filled the frame with NaN) is lowered by pnb-convert to the container's
  bound (kMaxLightOutput, with a warning); 30 cm above a floor it overexposes the frame to white
  but leaves no NaN or infinity in the radiance buffer (pnb-play's frame check, summary.json
  "frame_check", counts 0), as for the same scene with a sane light and for box-room. The check's
  counting itself is tested in frame_check_test.cpp (llvmpipe clamps RGBA16F overflow, so no
  scene here can make it non-zero).
- A debug view or a setting whose prerequisite is missing says what is missing; one that has an
  effect says nothing.

- A setting the GPU cannot honour (stream.upload_mib=4096: GL_OUT_OF_MEMORY, then a crash) falls
  back with a message naming it; an environment wider than every GL 4.5 GPU takes (65535x1) is
  stored at most 16384 wide and plays without a GL error; a larger texture (kept with
  --max-texture-size) is drawn from the first mip level the GPU takes, with a message.

usage: frame_check_test.py PNB_CONVERT PNB_PLAY BOX_ROOM.pnb WORKDIR
"""
import base64
import json
import os
import shutil
import struct
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from gltf_files import write_png, write_textured_triangle  # noqa: E402

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)


def floor_with_light(path, intensity):
    """A 4 m floor quad and a white point light 30 cm above its centre."""
    positions = struct.pack("<12f", -2, 0, -2, 2, 0, -2, 2, 0, 2, -2, 0, 2)
    normals = struct.pack("<12f", *([0, 1, 0] * 4))
    indices = struct.pack("<6H", 0, 2, 1, 0, 3, 2)
    data = positions + normals + indices
    doc = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "lamp", "type": "point", "intensity": intensity, "range": 10}]}},
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 96, "byteLength": 12}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                       "min": [-2, 0, -2], "max": [2, 0, 2]},
                      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                      {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "materials": [{"name": "floor", "pbrMetallicRoughness": {"metallicFactor": 0}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                    "material": 0}]}],
        "nodes": [{"mesh": 0}, {"extensions": {"KHR_lights_punctual": {"light": 0}},
                                "translation": [0, 0.3, 0]},
                  {"camera": 0, "translation": [0, 2.5, 2.5], "rotation": [-0.3826834, 0, 0, 0.9238795]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.05}}],
        "scenes": [{"nodes": [0, 1, 2]}], "scene": 0,
    }
    with open(path, "w") as f:
        json.dump(doc, f)


def play(play_exe, scene, out, *sets):
    command = [play_exe, scene, "--headless", "-q", "--size", "96x64", "--bench", "--frames", "1",
               "--out", out, "--screenshot", os.path.join(out, "frame.png")]
    for s in sets:
        command += ["--set", s]
    r = subprocess.run(command, capture_output=True, text=True, timeout=300)
    summary = {}
    if os.path.exists(os.path.join(out, "summary.json")):
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
    return r, summary


def main():
    convert, play_exe, box_room, work = map(os.path.abspath, sys.argv[1:5])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    os.chdir(work)

    floor_with_light("blinding.gltf", 3e38)
    r = subprocess.run([convert, "blinding.gltf", "-o", "blinding.pnb"], capture_output=True, text=True)
    check(r.returncode == 0, f"the blinding scene does not convert: {r.stderr}")
    check("intensity lowered to 1e+10" in r.stderr, f"no warning for the lowered light: {r.stderr}")
    check(os.path.exists("blinding.pnb"), "no container was written")

    floor_with_light("lamp.gltf", 20)
    r = subprocess.run([convert, "lamp.gltf", "-o", "lamp.pnb", "-q"], capture_output=True, text=True)
    check(r.returncode == 0, f"the lamp scene does not convert: {r.stderr}")
    for scene, out in (("blinding.pnb", "blinding"), ("lamp.pnb", "lamp"), (box_room, "box")):
        r, summary = play(play_exe, scene, out)
        check(r.returncode == 0 and "NaN or infinite" not in r.stderr,
              f"{scene}: a sane frame was flagged: {r.returncode} {r.stderr}")
        check(summary.get("frame_check", {}).get("nonfinite_pixels") == 0,
              f"{scene}: frame_check {summary.get('frame_check')}")

    # A documented setting the GPU cannot honour falls back with a message (it crashed):
    # three frames of 4096 MiB staging do not fit llvmpipe's buffers.
    r = subprocess.run([play_exe, box_room, "--headless", "-q", "--size", "96x64", "--stream",
                        "--set", "stream.upload_mib=4096", "--screenshot", "streamed.png"],
                       capture_output=True, text=True, timeout=300)
    check(r.returncode == 0 and "stream.upload_mib=4096: the GPU cannot hold" in r.stderr
          and os.path.exists("streamed.png"),
          f"stream.upload_mib=4096: exit {r.returncode}, {r.stderr.strip()[-600:]}")

    # Textures beyond what every GL 4.5 GPU takes are stored at 16384 at most (a 65535x1
    # environment converted and verified, then drew nothing but GL errors).
    write_png("wide.png", 65535, 1, (100, 150, 200))
    r = subprocess.run([convert, box_room.replace(".pnb", ".glb"), "-o", "wide.pnb",
                        "--environment", "wide.png"], capture_output=True, text=True)
    check(r.returncode == 0 and "16383x1" in r.stdout, f"the wide environment: {r.stdout} {r.stderr}")
    r = subprocess.run([play_exe, "wide.pnb", "--headless", "-q", "--size", "96x64", "--gl-debug",
                        "--screenshot", "wide-frame.png"], capture_output=True, text=True, timeout=300)
    check(r.returncode == 0 and "GL error" not in r.stderr, f"the wide environment plays with: {r.stderr}")

    # A texture larger than this GPU takes (kept by --max-texture-size): drawn from the first mip
    # level within the limit, with a message, and no GL error.
    write_png("big.png", 20000)
    write_textured_triangle("big.gltf", "big.png")
    r = subprocess.run([convert, "big.gltf", "-o", "portable.pnb"], capture_output=True, text=True)
    check(r.returncode == 0 and "20000x1 is larger than 16384" in r.stderr,
          f"a 20000-texel texture converts without the portable-size warning: {r.stderr}")
    r = subprocess.run([convert, "big.gltf", "-o", "big.pnb", "-q", "--max-texture-size", "65536"],
                       capture_output=True, text=True)
    r = subprocess.run([play_exe, "big.pnb", "--headless", "-q", "--size", "96x64", "--gl-debug",
                        "--screenshot", "big-frame.png"], capture_output=True, text=True, timeout=300)
    check(r.returncode == 0 and "drawn from mip level 1" in r.stderr and "GL error" not in r.stderr,
          f"a texture over the GPU's limit: exit {r.returncode}, {r.stderr}")

    notes = [
        (["debug.view=gi_rsm", "gi.enabled=false"], "debug.view=gi_rsm shows nothing: GI is off: gi.enabled is false"),
        (["debug.view=gi_indirect", "gi.enabled=false"], "debug.view=gi_indirect shows the lit image unchanged"),
        (["debug.view=histogram", "shadows.technique=pssm"], "the depth histogram is SDSM's"),
        (["debug.view=shadowmap", "shadows.technique=off"], "shows nothing: shadows.technique is off"),
        (["debug.view=lod"], "no item has levels of detail"),
        (["gi.cells=16"], "note: gi.cells has no effect: gi.enabled is false"),
        (["shadows.technique=single", "shadows.cascades=4"], "shadows.cascades has no effect: "
                                                             "shadows.technique single draws one map"),
        (["shadows.technique=off", "shadows.resolution=512"], "shadows.resolution has no effect"),
    ]
    for sets, expected in notes:
        r, _ = play(play_exe, box_room, "note", *sets)
        check(r.returncode == 0 and expected in r.stderr, f"{sets}: expected '{expected}' in: {r.stderr}")
    for sets in (["debug.view=shadowmap", "shadows.technique=pssm"],
                 ["debug.view=histogram", "shadows.technique=sdsm"]):
        r, _ = play(play_exe, box_room, "quiet", *sets)
        check(r.returncode == 0 and "note:" not in r.stderr, f"{sets}: an unexpected note: {r.stderr}")

    for f in failures:
        print("FAIL:", f, file=sys.stderr)
    if not failures:
        print(f"frame check: a light at the bound and sane frames clean, "
              f"{len(notes)} debug-view notes named what is missing")
        os.chdir("/")
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
