#!/usr/bin/env python3
"""Special files as inputs (issue 41, item 5): a FIFO, a directory or a device named where a tool
reads a file is refused at once with a message naming it, instead of blocking in open() forever
(`--environment FIFO` did) or failing obscurely. Every command runs under a 30 s limit: a hang
fails the test rather than the suite.

usage: special_inputs_test.py PNB_CONVERT PNB_EDIT PNB_PLAY PNB_INSPECT SOURCE.glb SCENE.pnb WORKDIR
"""
import os
import shutil
import subprocess
import sys


def main():
    convert, edit, play, inspect, source, scene, work = map(os.path.abspath, sys.argv[1:8])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    os.chdir(work)
    os.mkfifo("fifo")
    os.makedirs("dir")
    cases = [
        ("convert: the input is a FIFO", [convert, "fifo", "-o", "a.pnb"], "the input 'fifo' is a FIFO"),
        ("convert: --environment is a FIFO", [convert, source, "-o", "a.pnb", "--environment", "fifo"],
         "the environment image 'fifo' is a FIFO"),
        ("convert: --sidecar is a FIFO", [convert, source, "-o", "a.pnb", "--sidecar", "fifo"],
         "the sidecar 'fifo' is a FIFO"),
        ("convert: --path is a device", [convert, source, "-o", "a.pnb", "--path", "/dev/zero"],
         "the camera path '/dev/zero' is a device"),
        ("convert: the input is a directory", [convert, "dir", "-o", "a.pnb"], "the input 'dir' is a directory"),
        ("edit: the scene is a FIFO", [edit, "fifo", "--list"], "'fifo' is not a regular file"),
        ("edit: an imported image is a FIFO",
         [edit, scene, "--import-texture", "a=fifo", "-o", "e.pnb"], "the image imported as a 'fifo' is a FIFO"),
        ("play: the scene is a FIFO", [play, "fifo", "--headless", "-q", "--no-stream"],
         "'fifo' is not a regular file"),
        ("inspect: the file is a device", [inspect, "/dev/zero"], "'/dev/zero' is not a regular file"),
    ]
    failures = []
    for what, command, expected in cases:
        try:
            r = subprocess.run(command, capture_output=True, text=True, timeout=30)
        except subprocess.TimeoutExpired:
            failures.append(f"{what}: still running after 30 s")
            continue
        message = r.stdout + r.stderr
        if r.returncode == 0 or expected not in message:
            failures.append(f"{what}: exit {r.returncode}, expected '{expected}' in: {message.strip()}")
    for f in failures:
        print("FAIL:", f, file=sys.stderr)
    if not failures:
        print(f"special inputs: {len(cases)} refused at once, each named")
        os.chdir("/")
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
