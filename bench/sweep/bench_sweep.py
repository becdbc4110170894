#!/usr/bin/env python3
"""Time of one sweep on this machine, run by the local runner one job at a time, against the
same sweep as a Slurm job array with N slots (a single-node cluster started on loopback for the
bench: sweep/slurm_cluster.py, CPUs=N, array throttled to N), in the same session.

Both runs start from empty results directories (the scenes are containers: no conversion), use
the same binaries, so their jobs have the same keys. Reported: wall time of each run (the
Slurm one from sbatch to the collect job's end), jobs per minute, the ratio; per job, the median
GPU frame time of the array run against the local one (jobs that share the cores time each
other) and whether the error metrics are identical (they must be: same frames, same truth).

Usage: bench_sweep.py [SWEEP] [--slots N] [--out DIR] [--build DIR] [--order local,slurm]
Output: DIR/results.md, DIR/results.json, DIR/{local,slurm}/ (the results), DIR/report/.
"""
import argparse
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "sweep"))
import pnb_sweep  # noqa: E402
from slurm_cluster import LocalSlurmCluster  # noqa: E402


def sweep_cmd(build, *args):
    return [sys.executable, os.path.join(REPO, "sweep", "pnb_sweep.py"), "--build", build] + list(args)


def timed(cmd, env=None):
    t = time.monotonic()
    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL)
    return time.monotonic() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("sweep", nargs="?", default=os.path.join(REPO, "sweep", "examples", "shadows.toml"))
    ap.add_argument("--slots", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(REPO, "out", "bench", "sweep"))
    ap.add_argument("--build", default=os.path.join(REPO, "build", "release"))
    ap.add_argument("--order", default="local,slurm", help="which run goes first")
    a = ap.parse_args()
    out = os.path.abspath(a.out)
    dirs = {"local": os.path.join(out, "local"), "slurm": os.path.join(out, "slurm")}
    for d in dirs.values():
        shutil.rmtree(d, ignore_errors=True)
    os.makedirs(out, exist_ok=True)
    wall, window = {}, {}
    for run in a.order.split(","):
        if run == "local":
            wall[run] = timed(sweep_cmd(a.build, "run", "--local", a.sweep, "--results", dirs[run]))
        else:
            with LocalSlurmCluster(cpus=a.slots) as cluster:
                env = dict(os.environ, **cluster.env)
                wall[run] = timed(sweep_cmd(a.build, "run", "--slurm", a.sweep, "--results", dirs[run],
                                            "--throttle", str(a.slots), "--wait"), env)
        jobs = [pnb_sweep.read_json(os.path.join(dirs[run], k, "job.json")) for k in os.listdir(dirs[run])
                if os.path.exists(os.path.join(dirs[run], k, "job.json"))]
        window[run] = (min(j["started"] for j in jobs), max(j["finished"] for j in jobs), len(jobs))
        print("%s: %d jobs in %.1f s" % (run, len(jobs), wall[run]), flush=True)

    _, local_rows = pnb_sweep.collect(dirs["local"])
    _, slurm_rows = pnb_sweep.collect(dirs["slurm"])
    local = {r["key"]: r for r in local_rows}
    slurm = {r["key"]: r for r in slurm_rows}
    common = sorted(set(local) & set(slurm))
    gpu_ratio = [float(slurm[k]["gpu_ms:total"]) / float(local[k]["gpu_ms:total"]) for k in common]
    differ = [k for k in common if {c: v for c, v in local[k].items() if c.startswith("metric:")} !=
              {c: v for c, v in slurm[k].items() if c.startswith("metric:")}]
    n = len(local_rows)
    result = {
        "sweep": a.sweep, "jobs": n, "slots": a.slots, "order": a.order,
        "wall_s": wall, "jobs_per_min": {k: 60.0 * window[k][2] / v for k, v in wall.items()},
        "speedup_slurm_vs_local": wall["local"] / wall["slurm"],
        "gpu_ms_ratio_slurm_vs_local": {"median": statistics.median(gpu_ratio), "min": min(gpu_ratio),
                                        "max": max(gpu_ratio)},
        "jobs_with_different_metrics": len(differ), "jobs_compared": len(common),
        "machine": {"cores": os.cpu_count(), "kernel": platform.release(),
                    "gl_renderer": local_rows[0].get("gl_renderer", "")},
    }
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump(result, f, indent=2)
    with open(os.path.join(out, "results.md"), "w") as f:
        f.write("| run | jobs | wall s | jobs/min |\n|---|--:|--:|--:|\n")
        for k in a.order.split(","):
            f.write("| %s | %d | %.0f | %.2f |\n" % (
                "local runner, one job at a time" if k == "local" else "Slurm array, %d slots" % a.slots,
                window[k][2], wall[k], result["jobs_per_min"][k]))
        f.write("\nSlurm / local: wall time x%.2f; per-job median GPU frame time x%.2f (min %.2f, max %.2f); "
                "%d of %d jobs' error metrics differ.\n" % (
                    wall["slurm"] / wall["local"], result["gpu_ms_ratio_slurm_vs_local"]["median"],
                    min(gpu_ratio), max(gpu_ratio), len(differ), len(common)))
    subprocess.run(sweep_cmd(a.build, "report", dirs["local"], "-o", os.path.join(out, "report")), check=True,
                   stdout=subprocess.DEVNULL)
    print(open(os.path.join(out, "results.md")).read())
    return 0


if __name__ == "__main__":
    sys.exit(main())
