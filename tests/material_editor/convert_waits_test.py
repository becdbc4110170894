#!/usr/bin/env python3
"""pnb-convert -o onto a container another tool is saving (issue 44): the conversion's rename
waits for the other tool's lock (pnb/file_lock.h), says so, and lands after it; it never
replaces the file inside the other tool's read-to-rename. The other tool is this script holding
the same flock a pnb-edit save holds.

usage: convert_waits_test.py PNB_CONVERT SOURCE.glb WORKDIR
"""
import fcntl
import hashlib
import os
import shutil
import subprocess
import sys
import threading
import time


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def fail(message):
    print("FAIL:", message, file=sys.stderr)
    sys.exit(1)


def main():
    convert, source, work = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    target = os.path.join(work, "scene.pnb")
    first = subprocess.run([convert, source, "-o", target, "-q"], capture_output=True, text=True)
    if first.returncode != 0:
        fail(f"first conversion: {first.stderr}")
    before = digest(target)
    os.utime(target, (0, 0))  # any replacement now shows in the stamp too

    holder = open(target, "rb")
    fcntl.flock(holder, fcntl.LOCK_EX)  # "pnb-edit is saving"
    started = time.monotonic()
    proc = subprocess.Popen([convert, source, "-o", target], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    # Until the conversion reaches its rename and says it waits (a slow, sanitized build may
    # take a while to get there), then a little longer.
    lines = []
    reader = threading.Thread(target=lambda: lines.extend(proc.stderr), daemon=True)
    reader.start()
    while not any("waiting:" in l for l in lines) and proc.poll() is None:
        if time.monotonic() - started > 120:
            fail("the conversion neither finished nor said it was waiting within 120 s")
        time.sleep(0.05)
    time.sleep(1.0)
    if proc.poll() is not None:
        fail(f"the conversion finished while the file was locked: exit {proc.returncode}, "
             f"{''.join(lines)}")
    if os.stat(target).st_mtime != 0 or digest(target) != before:
        fail("the file was replaced while another tool held its lock")
    fcntl.flock(holder, fcntl.LOCK_UN)
    holder.close()
    proc.wait(timeout=120)
    reader.join(timeout=10)
    err = "".join(lines)
    waited = time.monotonic() - started
    if proc.returncode != 0:
        fail(f"the conversion failed after the lock was freed: {err}")
    if "waiting: another program is saving the output" not in err:
        fail(f"the conversion did not say it was waiting: {err}")
    if os.stat(target).st_mtime == 0:
        fail("the conversion did not replace the file once the lock was free")
    print(f"[ figure ] pnb-convert waited for the lock and replaced the file once it was free, "
          f"{waited:.1f} s after it started")
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
