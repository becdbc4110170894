#!/usr/bin/env python3
"""bench.startup_tiny: the experiment sweep/experiments/startup.toml in its tiny mode (one fresh
pnb-play per configuration on the box room), run through pnb-sweep as scripts/bench-startup runs
it, must write a CSV whose figures hang together, so the time-to-first-frame benchmark cannot
rot: every configuration present; no negative part; the parts add up to the total; the warm
launch takes every program from the program cache and the first launch compiles them all;
GPU-ready and the steady frame are positive; the job's figures (pnb-sweep's figures.json) are
the CSV's totals.

Usage: startup_tiny_test.py PNB_SWEEP_PY BUILD_DIR OUT_DIR
"""
import csv
import json
import os
import shutil
import subprocess
import sys

sweep, build, out = sys.argv[1:4]
experiment = os.path.join(os.path.dirname(os.path.abspath(sweep)), "experiments", "startup.toml")
shutil.rmtree(out, ignore_errors=True)
subprocess.run([sys.executable, sweep, "--build", build, "experiment", experiment, "--results", out,
                "--", "--tiny"], check=True)
jobs = [d for d in os.listdir(out) if os.path.exists(os.path.join(out, d, "job.json"))]
if len(jobs) != 1:
    sys.exit(f"FAIL: {len(jobs)} finished jobs in {out}, 1 expected")
job = os.path.join(out, jobs[0])
with open(os.path.join(job, "startup.csv")) as f:
    rows = {r["config"]: r for r in csv.DictReader(f)}
with open(os.path.join(job, "figures.json")) as f:
    figures = json.load(f)

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


for config, r in rows.items():
    name = f"{r['scene']}:{config}:{r['run']}:total"
    check(figures.get(name) == float(r["total"]), f"figure {name}: {figures.get(name)}, CSV {r['total']}")
check(os.path.exists(os.path.join(out, "report", "index.html")), "no report")

PARTS = ["process_start", "context", "load", "programs", "warmup", "first_frame", "other"]
for config in ["first-launch", "cold", "warm", "warm-no-warmup", "warm-no-cache"]:
    r = rows.get(config)
    check(r is not None, f"{config}: no row")
    if r is None:
        continue
    v = {k: float(x) for k, x in r.items() if k not in ("scene", "config", "run")}
    check(all(v[p] >= 0 for p in PARTS), f"{config}: a negative part {v}")
    check(abs(sum(v[p] for p in PARTS) - v["total"]) <= 1.0, f"{config}: parts do not add up {v}")
    check(v["gpu_ready"] > 0 and v["steady_frame"] > 0, f"{config}: GPU-ready or steady frame missing {v}")
check(int(rows["warm"]["compiled"]) == 0 and int(rows["warm"]["hits"]) > 0,
      f"warm launch compiled programs: {rows['warm']}")
check(int(rows["first-launch"]["hits"]) == 0 and int(rows["first-launch"]["compiled"]) > 0,
      f"first launch hit a cache: {rows['first-launch']}")
check(float(rows["warm-no-warmup"]["warmup"]) < 0.5, "warm-up ran with startup.warmup=false")

for f in failures:
    print("FAIL:", f)
print("bench.startup_tiny:", "ok" if not failures else f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
