#!/usr/bin/env python3
"""bench.load_tiny: runs the experiment sweep/experiments/load.toml (bench_load.py) with --tiny
through pnb-sweep, as scripts/bench-load does, and checks what it measured, not only that it ran.

usage: load_tiny_test.py PNB_SWEEP_PY BUILD_DIR OUT_DIR

Checks: every loader (pnb, assimp, tinygltf, floor) has a warm and a cold figure for the load
test; the GL loaders agree on its triangle and texture counts (the same scene reached the GPU);
the peers built full mip chains (64² textures: 7 levels each) and the .pnb brought more than one
level per texture; every cold run was preceded by an eviction; the floor read the same bytes as
its loader; results.md states how cold is made and what each loader includes; load.png is a PNG.
"""
import csv
import json
import shutil
import subprocess
import sys
from pathlib import Path

sweep, build, results = sys.argv[1], sys.argv[2], Path(sys.argv[3])
shutil.rmtree(results, ignore_errors=True)
subprocess.run([sys.executable, sweep, "--build", build, "experiment",
                str(Path(sweep).resolve().parent / "experiments" / "load.toml"), "--results", str(results),
                "--", "--tiny"], check=True, stdout=subprocess.DEVNULL)
jobs = [d for d in results.iterdir() if (d / "job.json").exists()]
if len(jobs) != 1:
    sys.exit(f"FAIL: {len(jobs)} finished jobs in {results}, 1 expected")
out = jobs[0]
with open(out / "results.csv") as f:
    rows = list(csv.DictReader(f))
with open(out / "figures.json") as f:
    figures = json.load(f)
failures = []
for r in rows:  # the job's figures are the CSV's medians
    name = f"{r['label']}:{r['cache']}:gpu_ready_ms_median"
    if figures.get(name) != float(r["gpu_ready_ms_median"]):
        failures.append(f"figure {name}: {figures.get(name)}, CSV {r['gpu_ready_ms_median']}")


def expect(ok, what):
    if not ok:
        failures.append(what)


lt = [r for r in rows if r["scene"] == "load-test"]
for loader in ("pnb", "assimp", "tinygltf", "floor"):
    for cache in ("warm", "cold"):
        m = [r for r in lt if r["loader"] == loader and r["cache"] == cache]
        expect(m, f"no {loader} {cache} figure for load-test")
        for r in m:
            expect(float(r["gpu_ready_ms_median"]) > 0, f"{r['label']} {cache}: no time")
gl = [r for r in lt if r["loader"] != "floor" and r["cache"] == "warm"]
tris = {r["label"]: int(r["triangles"]) for r in gl}
texs = {r["label"]: int(r["textures"]) for r in gl}
expect(len(set(tris.values())) == 1 and min(tris.values()) > 10000,
       f"loaders disagree on the load test's triangles: {tris}")
expect(len(set(texs.values())) == 1 and min(texs.values()) == 10,
       f"loaders disagree on the load test's textures: {texs}")
for r in gl:
    levels, n = int(r["mip_levels"]), int(r["textures"])
    if r["loader"] == "pnb":
        expect(levels > n, f"{r['label']}: {levels} mip levels for {n} textures")
    else:
        expect(levels == 7 * n, f"{r['label']}: {levels} mip levels for {n} 64² textures, "
                                "expected full chains (7 each)")
    expect(int(r["programs"]) >= 1, f"{r['label']}: no program linked")
for r in rows:
    if r["cache"] == "cold":
        expect(r.get("resident_after_evict_bytes_max", "") != "",
               f"{r['label']}: cold run without an eviction report")
    if r["loader"] != "floor":
        expect(float(r["floor_ms"]) > 0, f"{r['label']}: no floor")
models = {r["model"] for r in rows if r["scene"] == "models"}
expect(len(models) == 2, f"expected the two tiny models, got {sorted(models)}")
md = (out / "results.md").read_text()
expect("POSIX_FADV_DONTNEED" in md, "results.md does not say how cold is made")
expect("What each figure includes" in md, "results.md does not say what each loader includes")
expect((out / "load.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", "load.png is not a PNG")
if failures:
    print("\n".join(failures))
    sys.exit(1)
print(f"bench.load_tiny: {len(rows)} figures checked")
