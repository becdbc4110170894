#!/usr/bin/env python3
"""Time to first frame of pnb-play, from fresh processes (docs/PLAYER.md "Time to first frame").

Usage: bench_startup.py [--runs N] [--frames N] [--out DIR] [--build DIR] [SCENE.pnb ...]
       (default scenes: box-room and load-test, generated and converted into DIR if missing)
       bench_startup.py --tiny --build DIR --out OUT   # one run of each configuration on
       the box room with 2 steady frames (~10 s): the test bench.startup_tiny, so it cannot rot
The experiment sweep/experiments/startup.toml runs this (scripts/bench-startup runs that).

Every figure is one fresh pnb-play process (--headless --bench, --frames steady frames after the
first), N runs per configuration, configurations interleaved run by run; the page cache is warm
(each scene is read once before the runs). Process start is exact: the script passes
PNB_LAUNCH_TIME_NS (CLOCK_MONOTONIC just before it spawns the process). Configurations:
  first-launch     empty program cache, empty Mesa shader cache (a new machine or driver)
  cold             empty program cache, MESA_SHADER_CACHE_DISABLE=true (Mesa then offers no
                   program binary format: the program cache cannot be used either)
  warm             second launch: both caches filled by the previous run of the same series
  warm-no-warmup   warm, --set startup.warmup=false
  warm-no-cache    warm Mesa cache, --no-program-cache
Prints a table (median and min..max per part) and the goal check
TTFF <= 2 x (GPU-ready + one steady frame); writes DIR/startup.csv (one row per run).
"""
import argparse
import csv
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.join(ROOT, "build", "release")  # --build replaces it
PARTS = ["total", "process_start", "context", "load", "programs", "warmup", "first_frame", "other",
         "first_frame_thread_cpu"]
CONFIGS = ["first-launch", "cold", "warm", "warm-no-warmup", "warm-no-cache"]


def ensure_scene(name, out):
    path = os.path.join(out, name + ".pnb")
    if not os.path.exists(path):
        glb = os.path.join(out, name + ".glb")
        subprocess.run([os.path.join(BUILD, "assets_src", "pnb-make-scene"), name, glb], check=True,
                       stdout=subprocess.DEVNULL)
        subprocess.run([os.path.join(BUILD, "converter", "pnb-convert"), glb, "-o", path], check=True,
                       env=dict(os.environ, PNB_CACHE_DIR=os.path.join(out, "convert-cache")),
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return path


def run_once(scene, config, dirs, frames, out):
    env = dict(os.environ, EGL_LOG_LEVEL="fatal")
    args = []
    if config == "first-launch":
        program_cache, mesa_cache = tempfile.mkdtemp(dir=dirs), tempfile.mkdtemp(dir=dirs)
    elif config == "cold":
        program_cache, mesa_cache = tempfile.mkdtemp(dir=dirs), tempfile.mkdtemp(dir=dirs)
        env["MESA_SHADER_CACHE_DISABLE"] = "true"
    else:
        program_cache, mesa_cache = os.path.join(dirs, "warm-programs"), os.path.join(dirs, "warm-mesa")
        if config == "warm-no-warmup":
            args = ["--set", "startup.warmup=false"]
        if config == "warm-no-cache":
            args = ["--no-program-cache"]
    env["PNB_PROGRAM_CACHE_DIR"] = program_cache
    env["MESA_SHADER_CACHE_DIR"] = mesa_cache
    bench = os.path.join(out, "run")
    shutil.rmtree(bench, ignore_errors=True)
    cmd = [os.path.join(BUILD, "player", "pnb-play"), scene, "--headless", "--bench", "--frames", str(frames), "--fixed-dt", "--no-plot",
           "--out", bench, "-q"] + args
    env["PNB_LAUNCH_TIME_NS"] = str(time.clock_gettime_ns(time.CLOCK_MONOTONIC))
    subprocess.run(cmd, env=env, check=True)
    with open(os.path.join(bench, "summary.json")) as f:
        summary = json.load(f)
    t = summary["time_to_first_frame_ms"]
    with open(os.path.join(bench, "frames.csv")) as f:
        rows = list(csv.DictReader(f))
    steady = statistics.median(float(r["cpu_ms"]) + 0.0 for r in rows[1:]) if len(rows) > 1 else float("nan")
    gpu = summary["gpu_ms"].get("total", {}).get("median_ms", float("nan"))
    row = {p: t[p] for p in PARTS}
    row.update(gpu_ready=summary["load_ms"]["total"], steady_frame=max(steady, gpu),
               hits=t["program_cache"]["hits"], compiled=t["program_cache"]["misses"] +
               t["program_cache"]["rejected"] + t["program_cache"]["uncached"])
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--frames", type=int, default=8, help="frames after the first (steady frame)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench-startup"))
    ap.add_argument("--configs", default=",".join(CONFIGS))
    ap.add_argument("--build", default=BUILD, help="build tree whose pnb-play is timed")
    ap.add_argument("--tiny", action="store_true", help="1 run, 2 frames, the box room only")
    a = ap.parse_args()
    globals()["BUILD"] = os.path.abspath(a.build)
    if a.tiny:
        a.runs, a.frames = 1, 2
    os.makedirs(a.out, exist_ok=True)
    default_scenes = ["box-room"] if a.tiny else ["box-room", "load-test"]
    scenes = a.scenes or [ensure_scene(name, a.out) for name in default_scenes]
    configs = a.configs.split(",")
    rows = []
    for scene in scenes:
        with open(scene, "rb") as f:  # warm page cache
            while f.read(1 << 24):
                pass
        dirs = tempfile.mkdtemp(prefix="pnb-bench-startup-")
        try:
            if any(c.startswith("warm") for c in configs):  # fill both caches once
                run_once(scene, "warm", dirs, 1, a.out)
            for k in range(a.runs):
                for config in configs:
                    r = run_once(scene, config, dirs, a.frames, a.out)
                    r.update(scene=os.path.basename(scene), config=config, run=k)
                    rows.append(r)
                    print(f"{r['scene']:<16} {config:<15} run {k}: {r['total']:.0f} ms", file=sys.stderr)
        finally:
            shutil.rmtree(dirs, ignore_errors=True)

    with open(os.path.join(a.out, "startup.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["scene", "config", "run"] + PARTS +
                           ["gpu_ready", "steady_frame", "hits", "compiled"])
        w.writeheader()
        w.writerows(rows)

    def cell(values):
        return f"{statistics.median(values):7.1f} ({min(values):.0f}..{max(values):.0f})"

    print(f"pnb-play time to first frame, ms: median (min..max) of {a.runs} fresh processes; "
          f"warm page cache; {os.uname().nodename}")
    print(f"{'scene':<16} {'config':<15} " + " ".join(f"{p:>18}" for p in PARTS + ["gpu_ready", "steady_frame"]) +
          "  cache hits/compiled  goal TTFF <= 2 x (GPU-ready + steady)")
    for scene in dict.fromkeys(r["scene"] for r in rows):
        for config in configs:
            rs = [r for r in rows if r["scene"] == scene and r["config"] == config]
            if not rs:
                continue
            cols = " ".join(f"{cell([r[p] for r in rs]):>18}" for p in PARTS + ["gpu_ready", "steady_frame"])
            bound = 2 * (statistics.median(r["gpu_ready"] for r in rs) + statistics.median(r["steady_frame"] for r in rs))
            total = statistics.median(r["total"] for r in rs)
            print(f"{scene:<16} {config:<15} {cols}  {rs[0]['hits']:>4}/{rs[0]['compiled']:<4}"
                  f"  {total:.0f} {'<=' if total <= bound else '>'} {bound:.0f} {'met' if total <= bound else 'NOT met'}")
    print(f"wrote {os.path.join(a.out, 'startup.csv')}")


if __name__ == "__main__":
    main()
