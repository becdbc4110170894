#!/usr/bin/env python3
"""Special files as inputs, and long work shown (issue 41, item 5): a FIFO, a directory or a device
named where a tool reads a file is refused at once with a message naming it, instead of blocking in
open() forever (`--environment FIFO` did) or failing obscurely; every command runs under a 30 s
limit, so a hang fails the test rather than the suite. A long pnb-play run shows its progress on a
terminal, and writes none to a pipe.

usage: special_inputs_test.py PNB_CONVERT PNB_EDIT PNB_PLAY PNB_INSPECT SOURCE.glb SCENE.pnb WORKDIR
"""
import os
import pty
import select
import shutil
import subprocess
import sys
import time


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
    # Long work shows progress on a terminal (and only there): a long headless run, its stderr
    # on a pseudo-terminal, prints "frame K of N" after two seconds; stopped once it does.
    master, slave = pty.openpty()
    run = subprocess.Popen([play, scene, "--headless", "--size", "64x36", "--bench", "--frames", "100000",
                            "--out", "progress"], stdout=subprocess.DEVNULL, stderr=slave)
    os.close(slave)
    seen, deadline = b"", time.monotonic() + 120
    while b" of 100000" not in seen and time.monotonic() < deadline and run.poll() is None:
        if select.select([master], [], [], 1.0)[0]:
            try:
                seen += os.read(master, 4096)
            except OSError:
                break
    run.kill()
    run.wait()
    os.close(master)
    if b"frame " not in seen or b" of 100000" not in seen:
        failures.append(f"a long pnb-play run showed no progress on a terminal: {seen[-300:]!r}")
    quiet = subprocess.run([play, scene, "--headless", "--size", "64x36", "--bench", "--frames", "3",
                            "--out", "progress"], capture_output=True, text=True, timeout=300)
    if " of 3" in quiet.stderr:
        failures.append(f"progress was written to a pipe: {quiet.stderr}")

    for f in failures:
        print("FAIL:", f, file=sys.stderr)
    if not failures:
        print(f"special inputs: {len(cases)} refused at once, each named; progress shown on a terminal")
        os.chdir("/")
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
