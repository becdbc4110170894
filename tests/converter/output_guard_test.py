#!/usr/bin/env python3
"""Outputs never replace inputs (issue 41, item 1): pnb-convert (single and batch) and pnb-edit -o
(and pnb-play --screenshot) refuse an output that is, or resolves to, one of their inputs or another job's output (the same
path, a symlinked directory, a hard link, a file the conversion reads such as a glTF's image),
with an error naming both, exit code non-zero, and every input byte-identical afterwards.

usage: output_guard_test.py PNB_CONVERT PNB_EDIT PNB_PLAY SOURCE.glb SCENE.pnb WORKDIR
"""
import hashlib
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from gltf_files import write_png, write_textured_triangle  # noqa: E402

failures = []
tried = 0


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def refused(what, command, protected, names):
    """Runs `command`; it must fail, name every string in `names`, and leave `protected` intact."""
    global tried
    tried += 1
    before = {p: digest(p) for p in protected}
    r = subprocess.run(command, capture_output=True, text=True)
    message = r.stderr + r.stdout
    if r.returncode == 0:
        failures.append(f"{what}: exit 0 (it should refuse): {message.strip()}")
    for n in names:
        if n not in message:
            failures.append(f"{what}: the error does not name '{n}': {message.strip()}")
    for p, d in before.items():
        if digest(p) != d:
            failures.append(f"{what}: {p} was changed")
    return message


def main():
    convert, edit, play, source, scene, work = map(os.path.abspath, sys.argv[1:7])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    os.chdir(work)
    shutil.copyfile(source, "x.glb")
    shutil.copyfile(scene, "s.pnb")
    os.symlink(".", "here")
    os.link("x.glb", "hard.glb")
    os.makedirs("real")
    os.symlink("real", "alias")

    refused("convert onto its input", [convert, "x.glb", "-o", "x.glb"], ["x.glb"],
            ["the output (-o) 'x.glb'", "the input 'x.glb'"])
    refused("convert through a symlinked directory", [convert, "x.glb", "-o", "here/x.glb"],
            ["x.glb"], ["'here/x.glb'", "the input 'x.glb'"])
    refused("convert onto a hard link of its input", [convert, "x.glb", "-o", "hard.glb"],
            ["x.glb"], ["'hard.glb'", "the input 'x.glb'"])
    refused("summary onto the input",
            [convert, "x.glb", "-o", "out.pnb", "--summary-json", "x.glb"], ["x.glb"],
            ["the summary (--summary-json) 'x.glb'", "the input 'x.glb'"])
    # A file only the import reads: the glTF's image.
    write_png("tex.png", 4, 4)
    write_textured_triangle("tri.gltf", "tex.png")
    refused("convert onto the glTF's image", [convert, "tri.gltf", "-o", "tex.png"],
            ["tex.png", "tri.gltf"], ["'tex.png'", "a file the conversion read"])

    with open("list.txt", "w") as f:
        f.write("x.glb\treal/a.pnb\nx.glb\talias/a.pnb\n")
    refused("batch: two outputs that are one file", [convert, "--batch", "list.txt"], ["x.glb"],
            ["the output of list.txt:2 'alias/a.pnb'", "the output of list.txt:1 'real/a.pnb'"])
    shutil.copyfile("x.glb", "y.glb")
    with open("list2.txt", "w") as f:
        f.write("x.glb\ty.glb\ny.glb\tz.pnb\n")
    refused("batch: an output that is another item's input", [convert, "--batch", "list2.txt"],
            ["x.glb", "y.glb"], ["the output of list2.txt:1 'y.glb'", "the input of list2.txt:2"])
    with open("list3.txt", "wb") as f:
        f.write(b"x.glb\tq\0.pnb\n")
    refused("batch: a NUL byte in a path", [convert, "--batch", "list3.txt"], ["x.glb"],
            ["list3.txt:1", "NUL"])
    if os.path.exists("q"):
        failures.append("batch: a file was written for the line with a NUL byte")

    refused("edit -o onto an imported image",
            [edit, "s.pnb", "--import-texture", "red=tex.png", "--set", "white-wall.roughness=0.5",
             "-o", "here/tex.png"], ["s.pnb", "tex.png"],
            ["the output (-o) 'here/tex.png'", "the image imported as red 'tex.png'"])

    refused("a screenshot onto the scene",
            [play, "s.pnb", "--headless", "-q", "--screenshot", "here/s.pnb"], ["s.pnb"],
            ["the screenshot (--screenshot) 'here/s.pnb'", "the scene 's.pnb'"])

    # And what is allowed still works: a new output, and an edit in place through -o.
    ok = subprocess.run([convert, "x.glb", "-o", "real/ok.pnb", "-q"], capture_output=True, text=True)
    if ok.returncode != 0:
        failures.append(f"a plain conversion failed: {ok.stderr}")
    ok = subprocess.run([edit, "s.pnb", "-q", "--set", "white-wall.roughness=0.5", "-o", "here/s.pnb"],
                        capture_output=True, text=True)
    if ok.returncode != 0:
        failures.append(f"an edit in place through -o failed: {ok.stderr}")

    for f in failures:
        print("FAIL:", f, file=sys.stderr)
    if not failures:
        print(f"output guard: {tried} refusals named both files and left every input intact")
        os.chdir("/")
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
