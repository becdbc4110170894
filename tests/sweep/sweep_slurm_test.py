#!/usr/bin/env python3
"""pnb-sweep on a single-node Slurm cluster started on loopback for the test (sweep/slurm_cluster.py):
a 2-scene x 3-configuration sweep as an array job gives the local runner's results (identical
error metrics, timings present); a rerun submits nothing; a task cancelled before it ran is
listed as unfinished and its resubmission alone completes the set; a 4-file batch conversion as
an array gives the local conversion's bytes and is skipped when rerun; a command experiment's
jobs as an array write the figures the local runner writes, and its collect job tables them. Prints "SKIP: <reason>"
and exits 0 where the daemons cannot start (CTest reports the test as skipped).

Usage: sweep_slurm_test.py BUILD_DIR SCENE_DIR
"""
import os
import shutil
import subprocess
import sys
import tempfile
import types

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "sweep"))
import pnb_sweep  # noqa: E402
from slurm_cluster import ClusterUnavailable, LocalSlurmCluster  # noqa: E402


def check(condition, message):
    if not condition:
        raise AssertionError(message)


def sweep_text(scenes, techniques):
    text = 'name = "slurm"\nframes = 2\nsize = "64x36"\nmetrics = { shadow = 1 }\n'
    text += '[axes]\n"shadows.technique" = [%s]\n' % ", ".join('"%s"' % t for t in techniques)
    for s in scenes:
        text += '[[scenes]]\nsource = "%s"\n' % s
    return text


def metrics_by_key(results):
    columns, rows = pnb_sweep.collect(results)
    check("gpu_ms:total" in columns, "timings present")
    return {r["key"]: {c: v for c, v in r.items() if c.startswith("metric:") and "flicker" not in c} for r in rows}


def main(build, scenes):
    work = tempfile.mkdtemp(prefix="pnb_sweep_slurm_")
    try:
        with LocalSlurmCluster() as cluster:
            os.environ.update(cluster.env)  # sbatch, squeue, scancel see the test's cluster
            bins = pnb_sweep.binaries(build)
            scene_files = [os.path.join(scenes, n + ".pnb") for n in ("box-room", "grazing-plane")]
            sweep_file = os.path.join(work, "sweep.toml")
            with open(sweep_file, "w") as f:
                f.write(sweep_text(scene_files, ["off", "single", "pssm"]))
            sweep = pnb_sweep.load_sweep(sweep_file)
            local = pnb_sweep.plan(sweep, bins, os.path.join(work, "local"))
            for job in local["jobs"]:
                pnb_sweep.run_job(local, job["index"])
            on_cluster = pnb_sweep.plan(sweep, bins, os.path.join(work, "slurm"))
            args = types.SimpleNamespace(partition=None, gres=None, throttle=2)
            array, collect, n = pnb_sweep.slurm_submit(on_cluster, args)
            check(n == 6, "6 jobs submitted, not %d" % n)
            pnb_sweep.slurm_wait([array, collect], timeout=600)
            check(all(pnb_sweep.done(j) for j in on_cluster["jobs"]), "every job finished on the cluster")
            a, b = metrics_by_key(os.path.join(work, "local")), metrics_by_key(os.path.join(work, "slurm"))
            check(sorted(a) == sorted(b), "the same jobs (keys) locally and on the cluster")
            for key in a:
                check(a[key] == b[key], "job %s: metrics differ: %s vs %s" % (key, a[key], b[key]))
            check(os.path.exists(os.path.join(work, "slurm", "results.csv")), "the collect job ran")
            print("sweep: 6 jobs on the cluster, metrics identical to the local run")
            # A rerun submits nothing.
            array2, _, n2 = pnb_sweep.slurm_submit(on_cluster, args)
            check(n2 == 0 and array2 is None, "a rerun submits nothing")
            # A new axis value: 2 jobs; one task cancelled before it ran (throttle 1 keeps it queued).
            with open(sweep_file, "w") as f:
                f.write(sweep_text(scene_files, ["off", "single", "pssm", "lispsm"]))
            grown = pnb_sweep.plan(pnb_sweep.load_sweep(sweep_file), bins, os.path.join(work, "slurm"))
            pending = [j["index"] for j in grown["jobs"] if not pnb_sweep.done(j)]
            check(len(pending) == 2, "only the new value's 2 jobs are pending")
            array3, collect3, _ = pnb_sweep.slurm_submit(grown, types.SimpleNamespace(partition=None, gres=None,
                                                                                      throttle=1))
            subprocess.run(["scancel", "%s_%d" % (array3, pending[-1])], check=True)
            pnb_sweep.slurm_wait([array3, collect3], timeout=600)
            with open(os.path.join(work, "slurm", "failed.txt")) as f:
                failed = [int(line.split()[0]) for line in f if line.strip()]
            check(failed == [pending[-1]], "the cancelled task is listed as unfinished: %s" % failed)
            array4, collect4, n4 = pnb_sweep.slurm_submit(grown, args)
            check(n4 == 1, "only the unfinished job is resubmitted (%d)" % n4)
            pnb_sweep.slurm_wait([array4, collect4], timeout=600)
            check(all(pnb_sweep.done(j) for j in grown["jobs"]), "the set is complete")
            print("resubmission: the cancelled task alone completed the set")
            # Batch conversion: 4 sources as an array, against the local conversion.
            sources = os.path.join(work, "sources")
            os.makedirs(sources)
            for name in ("box-room", "grazing-plane", "street-canyon", "atrium"):
                shutil.copy(os.path.join(scenes, name + ".glb"), sources)
            check(pnb_sweep.main(["--build", build, "convert", "--local", sources, "-o",
                                  os.path.join(work, "conv-local")]) == 0, "local conversion")
            check(pnb_sweep.main(["--build", build, "convert", "--slurm", "--wait", sources, "-o",
                                  os.path.join(work, "conv-slurm")]) == 0, "conversion array")
            for name in ("box-room", "grazing-plane", "street-canyon", "atrium"):
                with open(os.path.join(work, "conv-local", name + ".pnb"), "rb") as x, \
                        open(os.path.join(work, "conv-slurm", name + ".pnb"), "rb") as y:
                    check(x.read() == y.read(), "%s: the same bytes on the cluster" % name)
            before = {f: os.path.getmtime(os.path.join(work, "conv-slurm", f))
                      for f in os.listdir(os.path.join(work, "conv-slurm")) if f.endswith(".pnb")}
            jobs_before = len(os.listdir(os.path.join(work, "conv-slurm", "slurm")))
            check(pnb_sweep.main(["--build", build, "convert", "--slurm", "--wait", sources, "-o",
                                  os.path.join(work, "conv-slurm")]) == 0, "conversion rerun")
            for f, t in before.items():
                check(os.path.getmtime(os.path.join(work, "conv-slurm", f)) == t, "%s skipped on rerun" % f)
            check(len(os.listdir(os.path.join(work, "conv-slurm", "slurm"))) == jobs_before,
                  "an up-to-date rerun submits nothing (no new task logs)")
            print("conversion: 4 files on the cluster, byte-identical to local, skipped on rerun")
            # A command experiment (kind = "command") as an array: each task writes its figures.
            command_file = os.path.join(work, "command.toml")
            with open(command_file, "w") as f:
                f.write('name = "cmd"\nkind = "command"\ncommand = ["{python}", "-c", "import json; '
                        'json.dump({\'square\': {n} * {n}}, open(\'{out}/figures.json\', \'w\'))"]\n'
                        '[axes]\nn = [2, 3, 5]\n')
            experiment = pnb_sweep.load_sweep(command_file)
            cmd_bins = pnb_sweep.binaries(build, "command")
            cmd_plan = pnb_sweep.plan(experiment, cmd_bins, os.path.join(work, "cmd"))
            array5, collect5, n5 = pnb_sweep.slurm_submit(cmd_plan, args)
            check(n5 == 3, "3 command jobs submitted, not %d" % n5)
            pnb_sweep.slurm_wait([array5, collect5], timeout=600)
            _, rows = pnb_sweep.collect(os.path.join(work, "cmd"))
            check(sorted(r["fig:square"] for r in rows) == [4, 9, 25], "the array's figures: %s" % rows)
            with open(os.path.join(work, "cmd", "results.csv")) as f:
                check("fig:square" in f.readline(), "the collect job tabled the figures")
            print("command experiment: 3 jobs on the cluster, their figures collected")
    except ClusterUnavailable as e:
        print("SKIP: no Slurm cluster can start here: %s" % e.reason)
        return 0
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])))
