#!/usr/bin/env python3
"""Test of player/tools/plot_frames.py: plots are produced from the fixture (single run and
--compare), and missing or malformed CSVs fail with exit status 2, a message, and no output.

    plot_frames_test.py PLOT_FRAMES_PY FIXTURE_CSV
"""

import os
import shutil
import subprocess
import sys
import tempfile

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def run(script, *args):
    return subprocess.run([sys.executable, script, *args], capture_output=True, text=True)


def check(condition, message):
    if not condition:
        print(f"FAIL: {message}")
        sys.exit(1)


def expect_png(result, path, what):
    check(result.returncode == 0, f"{what}: exit {result.returncode}: {result.stderr}")
    check(os.path.isfile(path), f"{what}: {path} was not written")
    with open(path, "rb") as f:
        head = f.read(8)
    check(head == PNG_SIGNATURE, f"{what}: {path} is not a PNG")
    check(os.path.getsize(path) > 5000, f"{what}: {path} is suspiciously small")


def expect_error(result, out, what, mentions):
    check(result.returncode == 2, f"{what}: expected exit 2, got {result.returncode}")
    check("plot_frames.py: error:" in result.stderr, f"{what}: no error message: {result.stderr!r}")
    check(mentions in result.stderr, f"{what}: message lacks {mentions!r}: {result.stderr!r}")
    check(not os.path.exists(out), f"{what}: {out} was written anyway")


def main():
    script, fixture = sys.argv[1], sys.argv[2]
    tmp = tempfile.mkdtemp(prefix="pnb_plot_frames_")
    try:
        out = os.path.join(tmp, "frames.png")
        expect_png(run(script, fixture, out, "--title", "fixture"), out, "single run")

        # A second run for --compare: the same path, slower.
        other = os.path.join(tmp, "forward.csv")
        with open(fixture) as f, open(other, "w") as g:
            lines = f.read().splitlines()
            g.write(lines[0] + "\n")
            for line in lines[1:]:
                cells = line.split(",")
                if cells[3]:
                    cells[3] = f"{float(cells[3]) * 1.4:.3f}"
                g.write(",".join(cells) + "\n")
        cmp_out = os.path.join(tmp, "compare.png")
        expect_png(run(script, fixture, cmp_out, "--compare", other, "--labels", "deferred",
                       "forward"), cmp_out, "compare")
        cmp2 = os.path.join(tmp, "compare2.png")
        expect_png(run(script, fixture, cmp2, "--compare", other), cmp2, "compare, default labels")
        check(sorted(os.listdir(tmp)) == ["compare.png", "compare2.png", "forward.csv",
                                          "frames.png"], f"leftover files: {os.listdir(tmp)}")

        def bad(name, text):
            path = os.path.join(tmp, name)
            with open(path, "w") as f:
                f.write(text)
            return path

        bad_out = os.path.join(tmp, "bad.png")
        expect_error(run(script, os.path.join(tmp, "missing.csv"), bad_out), bad_out,
                     "missing file", "cannot read")
        expect_error(run(script, bad("empty.csv", ""), bad_out), bad_out, "empty file", "empty")
        expect_error(run(script, bad("nocol.csv", "frame,time_s,cpu_ms\n0,0,1\n"), bad_out),
                     bad_out, "missing column", "gpu_total_ms")
        expect_error(run(script, bad("nan.csv", "frame,time_s,cpu_ms,gpu_total_ms\n0,0,x,1\n"),
                         bad_out), bad_out, "non-number", "cpu_ms")
        expect_error(run(script, bad("fields.csv", "frame,time_s,cpu_ms,gpu_total_ms\n0,0,1\n"),
                         bad_out), bad_out, "field count", "3 fields")
        expect_error(run(script, bad("norows.csv", "frame,time_s,cpu_ms,gpu_total_ms\n"), bad_out),
                     bad_out, "no rows", "no data rows")
        expect_error(run(script, fixture, bad_out, "--compare", os.path.join(tmp, "nope.csv")),
                     bad_out, "missing compare file", "nope.csv")
        expect_error(run(script, fixture, os.path.join(tmp, "no_dir", "x.png")),
                     os.path.join(tmp, "no_dir", "x.png"), "missing output directory",
                     "does not exist")
        usage = run(script, fixture, bad_out, "--labels", "a", "b")
        check(usage.returncode == 2 and "--labels needs --compare" in usage.stderr,
              f"--labels without --compare: {usage.returncode} {usage.stderr!r}")
    finally:
        shutil.rmtree(tmp)
    print("plot_frames_test: ok")


if __name__ == "__main__":
    main()
