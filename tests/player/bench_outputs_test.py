#!/usr/bin/env python3
"""player.bench.<scene>: the benchmark harness end to end on one scene, and what it writes.

Runs `pnb-play SCENE --headless --bench --frames N --fixed-dt --size WxH --out DIR -q` with a
screenshot of the last frame, into an emptied DIR, then checks the outputs (pnb_player/benchmark.h
says what each holds):
  frames.csv     the header's columns; N rows, frames 0..N-1 at path times k*dt; finite positive
                 CPU and frame times; finite non-negative GPU times; finite camera, a field of view
                 in (0, 180); something drawn
  summary.json   parses; run (frames, size, fixed step) as asked; CPU and GPU statistics ordered
                 (min <= median <= p95 <= max) and matching frames.csv; one GPU entry per CSV pass
                 plus "total"; no NaN or infinite pixel in the last frame; load time and memory
  frame_times.png  a PNG, written exactly when pnb-play's python3 has matplotlib (else absent)
  the screenshot a PNG of W x H
and that nothing else is left in DIR (no plot script, no temporary file).

Usage: bench_outputs_test.py PNB_PLAY SCENE.pnb OUT_DIR [FRAMES [WxH]]
"""
import csv
import json
import math
import os
import shutil
import struct
import subprocess
import sys

FIXED_COLUMNS = ["frame", "time_s", "cpu_ms", "gpu_total_ms"]
STAT_COLUMNS = ["draw_calls", "triangles", "visible_items", "culled_items", "deferred_layers",
                "shadow_draws", "shadow_triangles", "shadow_casters", "camera_x", "camera_y",
                "camera_z", "camera_yfov_deg", "thread_cpu_ms", "lod_switches", "frame_ms"]

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
    return ok


def number(text, column, row):
    try:
        return float(text)
    except ValueError:
        check(False, "frames.csv row %d: %s is %r, not a number" % (row, column, text))
        return math.nan


def png_size(path):
    """(width, height) from the PNG signature and IHDR, or None."""
    with open(path, "rb") as f:
        head = f.read(24)
    if len(head) < 24 or head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        return None
    return struct.unpack(">II", head[16:24])


def plot_expected():
    """Whether pnb-play can plot: the interpreter it picks (plot_script.cpp) imports matplotlib."""
    python = os.environ.get("PNB_PYTHON") or ("/usr/bin/python3" if os.path.exists("/usr/bin/python3")
                                               else "python3")
    return subprocess.run([python, "-c", "import matplotlib"], capture_output=True).returncode == 0


def check_csv(path, frames):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    check(header[:4] == FIXED_COLUMNS, "frames.csv starts with %s, not %s" % (header[:4], FIXED_COLUMNS))
    passes = [c[4:-3] for c in header if c.startswith("gpu_") and c.endswith("_ms") and c != "gpu_total_ms"]
    check(header == FIXED_COLUMNS + ["gpu_%s_ms" % p for p in passes] + STAT_COLUMNS,
          "frames.csv columns: %s" % header)
    check(len(body) == frames, "frames.csv has %d rows, not %d" % (len(body), frames))
    table = []
    for k, row in enumerate(body):
        if not check(len(row) == len(header), "frames.csv row %d has %d fields, not %d" % (k, len(row), len(header))):
            continue
        r = {c: (number(v, c, k) if v != "" else None) for c, v in zip(header, row)}
        table.append(r)
        check(r["frame"] == k, "frames.csv row %d is frame %s" % (k, r["frame"]))
        for c in ("cpu_ms", "frame_ms"):
            check(r[c] is not None and math.isfinite(r[c]) and r[c] > 0, "frame %d: %s = %s, not > 0" % (k, c, r[c]))
        for c in ["gpu_total_ms", "thread_cpu_ms"] + ["gpu_%s_ms" % p for p in passes]:
            check(r[c] is None or (math.isfinite(r[c]) and r[c] >= 0), "frame %d: %s = %s" % (k, c, r[c]))
        for c in ("camera_x", "camera_y", "camera_z", "time_s"):
            check(r[c] is not None and math.isfinite(r[c]), "frame %d: %s = %s" % (k, c, r[c]))
        check(r["camera_yfov_deg"] is not None and 0 < r["camera_yfov_deg"] < 180,
              "frame %d: camera_yfov_deg = %s" % (k, r["camera_yfov_deg"]))
        for c in STAT_COLUMNS[:8] + ["lod_switches"]:
            check(r[c] is not None and r[c] >= 0 and r[c] == int(r[c]), "frame %d: %s = %s" % (k, c, r[c]))
    check(any(r["draw_calls"] and r["triangles"] for r in table), "no frame drew anything")
    return table, passes


def ordered(stats, name):
    keys = ("min_ms", "median_ms", "p95_ms", "max_ms")
    values = [stats.get(k) for k in keys]
    if not check(all(isinstance(v, (int, float)) and math.isfinite(v) for v in values),
                 "summary.json %s: %s" % (name, stats)):
        return False
    return check(values == sorted(values), "summary.json %s is not ordered: %s" % (name, stats))


def close(a, b):  # frames.csv keeps 6 significant digits
    return abs(a - b) <= 1e-5 * max(abs(a), abs(b)) + 1e-9


def check_summary(path, table, passes, frames, width, height):
    with open(path) as f:
        s = json.load(f)
    run = s["run"]
    check(run["frames"] == frames, "summary.json run.frames = %s" % run["frames"])
    check((run["width"], run["height"]) == (width, height), "summary.json size %sx%s" % (run["width"], run["height"]))
    check(run["fixed_dt"] is True and run["dt_s"] > 0, "summary.json run: fixed_dt %s, dt_s %s" % (run["fixed_dt"], run["dt_s"]))
    for k, r in enumerate(table):
        check(close(r["time_s"], k * run["dt_s"]), "frame %d at path time %s, not %s" % (k, r["time_s"], k * run["dt_s"]))
    if run["path_duration_s"] > 0:
        check(close(run["dt_s"] * frames, run["path_duration_s"]),
              "%d steps of %s s do not cover the path's %s s" % (frames, run["dt_s"], run["path_duration_s"]))
    if ordered(s["cpu_ms"], "cpu_ms"):
        cpu = [r["cpu_ms"] for r in table]
        check(close(s["cpu_ms"]["min_ms"], min(cpu)) and close(s["cpu_ms"]["max_ms"], max(cpu)),
              "summary.json cpu_ms %s does not match frames.csv (%s..%s)" % (s["cpu_ms"], min(cpu), max(cpu)))
    check(sorted(s["gpu_ms"]) == sorted(passes + ["total"]),
          "summary.json gpu_ms passes %s, frames.csv %s" % (sorted(s["gpu_ms"]), passes))
    for name, stats in s["gpu_ms"].items():
        ordered(stats, "gpu_ms." + name)
    totals = [r["gpu_total_ms"] for r in table if r["gpu_total_ms"] is not None]
    if totals and check("total" in s["gpu_ms"], "summary.json gpu_ms has no total"):
        check(close(s["gpu_ms"]["total"]["max_ms"], max(totals)), "summary.json gpu_ms.total.max does not match frames.csv")
    check(s["frame_check"] == {"frame": frames - 1, "nonfinite_pixels": 0}, "frame_check: %s" % s["frame_check"])
    check(s["scene"]["triangles"] > 0 and s["scene"]["draw_items"] > 0, "summary.json scene: %s" % s["scene"])
    check(s["load_ms"]["total"] > 0 and s["load_ms"]["file_bytes"] > 0, "summary.json load_ms: %s" % s["load_ms"])
    check(s["peak_rss_bytes"] > 0, "summary.json peak_rss_bytes = %s" % s["peak_rss_bytes"])
    check(s["triangles"]["sum"] == sum(int(r["triangles"]) for r in table), "summary.json triangles.sum")
    check("time_to_first_frame_ms" in s and s["time_to_first_frame_ms"]["total"] > 0,
          "summary.json has no time to first frame")


def main():
    if len(sys.argv) not in (4, 5, 6):
        sys.exit(__doc__)
    play, scene, out = sys.argv[1:4]
    frames = int(sys.argv[4]) if len(sys.argv) > 4 else 12
    width, height = map(int, (sys.argv[5] if len(sys.argv) > 5 else "160x90").split("x"))
    shutil.rmtree(out, ignore_errors=True)  # stale outputs must not pass
    shot = os.path.join(out, "last_frame.png")
    cmd = [play, scene, "--headless", "--bench", "--frames", str(frames), "--fixed-dt",
           "--size", "%dx%d" % (width, height), "--out", out, "--screenshot", shot,
           "--frame", str(frames - 1), "-q"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("FAIL: %s exited %d\n%s%s" % (" ".join(cmd), p.returncode, p.stdout, p.stderr))
    expected = {"frames.csv", "summary.json", "last_frame.png"}
    if plot_expected():
        expected.add("frame_times.png")
    present = set(os.listdir(out))
    check(present == expected, "%s holds %s, expected %s" % (out, sorted(present), sorted(expected)))
    if "frames.csv" in present and "summary.json" in present:
        table, passes = check_csv(os.path.join(out, "frames.csv"), frames)
        check_summary(os.path.join(out, "summary.json"), table, passes, frames, width, height)
    if "frame_times.png" in present:
        size = png_size(os.path.join(out, "frame_times.png"))
        check(size is not None and size[0] > 0 and size[1] > 0, "frame_times.png is not a PNG: %s" % (size,))
    if "last_frame.png" in present:
        check(png_size(shot) == (width, height), "the screenshot is %s, not %dx%d" % (png_size(shot), width, height))
    for f in failures:
        print("FAIL: " + f)
    if failures:
        return 1
    print("ok: %s: %d frames, outputs %s" % (os.path.basename(scene), frames, sorted(present)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
