#!/usr/bin/env python3
"""bench.anim_quick: scripts/bench-anim's measurement (bench/anim/bench_anim.py) in --quick mode on
one walker with tiny frame counts, sizes and sample counts, must run end to end and write its CSV
and markdown summary with every row and column the benchmark reports: the crowd's animated and
frozen rows with frame times and their ratio, and the moving-light rows with the GI, shadow and
whole-frame errors, the GI passes' cost and the temporal-stability figures. It checks that the
figures are there and well-formed, not their values (before the player and the converter play
animation, animated and frozen are the same frames and the summary says the animation is absent).

Usage: anim_quick_test.py BENCH_ANIM_PY BUILD_DIR OUT_DIR
"""
import csv
import math
import os
import shutil
import subprocess
import sys

script, build, out = sys.argv[1:4]
shutil.rmtree(out, ignore_errors=True)
subprocess.run([sys.executable, script, "--build", build, "--out", out, "--quick", "--counts", "1",
                "--frames", "3", "--rounds", "1", "--size", "160x90", "--ml-size", "96x54",
                "--ml-frames", "2", "--every", "1", "--gi-samples", "4", "--frame-samples", "4",
                "--frame-time-limit", "2", "--stability-frames", "2", "--truth-spp", "4"], check=True)

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


def number(row, key):
    try:
        return float(row[key])
    except (KeyError, ValueError):
        return math.nan


with open(os.path.join(out, "anim.csv")) as f:
    reader = csv.DictReader(f)
    columns = reader.fieldnames or []
    rows = list(reader)
for c in ["scene", "state", "count", "technique", "anim_present", "frame_ms", "frame_ratio", "gpu_ms",
          "deform_ms", "gi_rmse_pct", "gi_ratio", "misclassified_pct", "shadow_ratio", "frame_flip_ldr",
          "flip_ratio", "gi_ms", "image_change", "truth_change", "change_ratio"]:
    check(c in columns, f"anim.csv lacks column {c}")

crowd = {r["state"]: r for r in rows if r["scene"] == "crowd" and r["count"] == "1"}
light = {r["state"]: r for r in rows if r["scene"] == "moving-light" and r["technique"] == "lpv"}
for name, group in (("crowd", crowd), ("moving-light", light)):
    for state in ("animated", "frozen"):
        check(state in group, f"no {name} {state} row")
if not failures:
    for state in ("animated", "frozen"):
        check(number(crowd[state], "frame_ms") > 0, f"crowd {state}: frame_ms {crowd[state]['frame_ms']}")
        check(number(crowd[state], "triangles") >= 1000, f"crowd {state}: triangles {crowd[state]['triangles']}")
        check(number(light[state], "gi_rmse_pct") >= 0, f"moving-light {state}: no GI error")
        check(number(light[state], "misclassified_pct") >= 0, f"moving-light {state}: no shadow figure")
        check(number(light[state], "frame_flip_ldr") >= 0, f"moving-light {state}: no FLIP")
        check(number(light[state], "gi_ms") > 0, f"moving-light {state}: no GI pass time")
        check(crowd[state]["anim_present"] in ("True", "False"), "anim_present is not a flag")
    check(number(crowd["frozen"], "frame_ratio") == 1.0, "the frozen row's ratio is not 1")
    check(number(crowd["animated"], "frame_ratio") > 0, "no animated/frozen ratio")
    check(number(light["animated"], "image_change") >= 0 and number(light["animated"], "truth_change") >= 0,
          "no temporal-stability figures")

with open(os.path.join(out, "summary.md")) as f:
    summary = f.read()
for text in ("## crowd", "| walkers |", "## moving-light", "| technique | state |", "temporal stability"):
    check(text in summary, f"summary.md lacks '{text}'")
absent = crowd.get("animated", {}).get("anim_present") == "False"
check(absent == ("Animation absent" in summary), "summary.md and anim.csv disagree on the animation's presence")
for p in ("scenes/crowd-1.glb", "scenes/crowd-1.pnb", "scenes/moving-light.pnb"):
    check(os.path.exists(os.path.join(out, p)), f"no {p}")

if failures:
    print("FAIL:\n  " + "\n  ".join(failures))
    sys.exit(1)
print("bench-anim quick: CSV, summary and runs are complete")
