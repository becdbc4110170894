#!/usr/bin/env python3
"""sweep.slurm_cluster: a single-node Slurm cluster on loopback (sweep/slurm_cluster.py), started
inside the test and stopped by it: a throttled array job writes one file per task; a killed task is
found by its missing output and resubmitted alone; a dependent job runs after an array; at the end
the daemons' own PIDs are gone and no job process is left.

When the cluster cannot start here (no slurm-wlm or munge, a daemon that does not come up) the
test prints "SKIP: <reason>" and exits 0 (CTest's SKIP_REGULAR_EXPRESSION shows it as skipped).

Usage: slurm_cluster_test.py [unittest options]
"""
import os
import shutil
import sys
import tempfile
import time
import unittest
from pathlib import Path

# sweep/ on the path, as the other sweep tests do: the module is `slurm_cluster`.
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "sweep"))
import slurm_cluster  # noqa: E402
from slurm_cluster import ClusterUnavailable, LocalSlurmCluster  # noqa: E402

# One task's work: its start and end times in out/<task>.txt (written whole or not at all).
# A file named slow-<task> in the job's directory makes that task sleep far longer than the test.
TASK = """#!/bin/bash
#SBATCH --output=log/%x-%A_%a.out
set -eu
start=$(date +%s.%N)
if [ -e "slow-$SLURM_ARRAY_TASK_ID" ]; then sleep 300; fi
sleep "${TASK_SECONDS:-0}"
mkdir -p out
echo "$SLURM_ARRAY_TASK_ID $SLURM_ARRAY_JOB_ID $start $(date +%s.%N)" > "out/$SLURM_ARRAY_TASK_ID.tmp"
mv "out/$SLURM_ARRAY_TASK_ID.tmp" "out/$SLURM_ARRAY_TASK_ID.txt"
"""

# Runs once the array is over (afterany): which outputs exist, and when it started.
SUMMARY = """#!/bin/bash
#SBATCH --output=log/summary-%j.out
set -eu
echo "start $(date +%s.%N)" > summary.tmp
ls out | sort >> summary.tmp
mv summary.tmp summary.txt
"""

CLUSTER = None
UNAVAILABLE = None


def read_tasks(out: Path) -> dict[int, tuple[float, float]]:
    tasks = {}
    for f in out.glob("*.txt"):
        task, _job, start, end = f.read_text().split()
        tasks[int(task)] = (float(start), float(end))
    return tasks


class ClusterUnavailableTest(unittest.TestCase):
    def test_missing_binary_is_a_reason(self):
        saved = slurm_cluster.BINARIES
        slurm_cluster.BINARIES = saved + ("pnb-no-such-slurm-binary",)
        try:
            with self.assertRaises(ClusterUnavailable) as e:
                with LocalSlurmCluster():
                    pass
            self.assertIn("pnb-no-such-slurm-binary", e.exception.reason)
        finally:
            slurm_cluster.BINARIES = saved


class LocalSlurmClusterTest(unittest.TestCase):
    """The tests run in name order on one cluster; test_9 stops it."""

    @classmethod
    def setUpClass(cls):
        global CLUSTER, UNAVAILABLE
        # 4 CPUs whatever the machine has (config_overrides), so that the throttle, not the CPU
        # count, is what limits the array to 2 tasks at once. The tasks mostly sleep.
        cls.cluster = LocalSlurmCluster(cpus=4, start_timeout=30)
        try:
            cls.cluster.start()
        except ClusterUnavailable as e:
            UNAVAILABLE = e.reason
            raise unittest.SkipTest(e.reason)
        CLUSTER = cls.cluster
        cls.jobs = Path(tempfile.mkdtemp(prefix="pnb-slurm-jobs-"))
        (cls.jobs / "task.sh").write_text(TASK)
        (cls.jobs / "summary.sh").write_text(SUMMARY)

    @classmethod
    def tearDownClass(cls):
        cls.cluster.stop()
        shutil.rmtree(cls.jobs, ignore_errors=True)

    def job_dir(self, name: str) -> Path:
        d = self.jobs / name
        (d / "log").mkdir(parents=True)
        return d

    def test_1_throttled_array(self):
        d = self.job_dir("throttled")
        job = self.cluster.submit_array(self.jobs / "task.sh", 4, throttle=2, cwd=d,
                                        extra_args=["--job-name=throttled",
                                                    "--export=ALL,TASK_SECONDS=1"])
        states = self.cluster.wait([job], timeout=30)
        self.assertEqual(states, {f"{job}_{i}": "COMPLETED" for i in range(4)})
        tasks = read_tasks(d / "out")
        self.assertEqual(sorted(tasks), [0, 1, 2, 3])
        # Never more than 2 at once: at every task's start, at most 2 are running.
        for s, _ in tasks.values():
            running = sum(1 for s2, e2 in tasks.values() if s2 <= s < e2)
            self.assertLessEqual(running, 2, tasks)

    def test_2_killed_task_is_resubmitted(self):
        d = self.job_dir("killed")
        (d / "slow-2").touch()
        job = self.cluster.submit_array(self.jobs / "task.sh", 4, cwd=d,
                                        extra_args=["--job-name=killed"])
        deadline = time.monotonic() + 20
        while self.cluster.states([job]).get(f"{job}_2") != "RUNNING":
            self.assertLess(time.monotonic(), deadline, "task 2 never ran")
            time.sleep(0.2)
        self.cluster.run(["scancel", f"{job}_2"])
        states = self.cluster.wait([job], timeout=30)
        self.assertEqual(states[f"{job}_2"], "CANCELLED")
        # What a sweep does: the tasks whose output is missing are the ones to run again.
        missing = sorted({0, 1, 2, 3} - set(read_tasks(d / "out")))
        self.assertEqual(missing, [2])
        (d / "slow-2").unlink()
        again = self.cluster.submit_array(self.jobs / "task.sh", ",".join(map(str, missing)),
                                          cwd=d, extra_args=["--job-name=killed"])
        self.assertEqual(self.cluster.wait([again], timeout=30), {f"{again}_2": "COMPLETED"})
        self.assertEqual(sorted(read_tasks(d / "out")), [0, 1, 2, 3])
        self.assertEqual((d / "out" / "2.txt").read_text().split()[1], again)

    def test_3_dependent_job_runs_after_the_array(self):
        d = self.job_dir("dependency")
        job = self.cluster.submit_array(self.jobs / "task.sh", 3, cwd=d,
                                        extra_args=["--job-name=dep",
                                                    "--export=ALL,TASK_SECONDS=1"])
        summary = self.cluster.submit([f"--dependency=afterany:{job}", "--job-name=summary",
                                       str(self.jobs / "summary.sh")], cwd=d)
        states = self.cluster.wait([job, summary], timeout=30)
        self.assertEqual(states[summary], "COMPLETED", states)
        lines = (d / "summary.txt").read_text().split("\n")
        self.assertEqual(lines[1:4], ["0.txt", "1.txt", "2.txt"])
        summary_start = float(lines[0].split()[1])
        last_end = max(e for _, e in read_tasks(d / "out").values())
        self.assertGreaterEqual(summary_start, last_end)

    def test_9_stop_by_pid(self):
        pids = dict(self.cluster.pids)
        root = self.cluster.root
        self.assertEqual(set(pids), {"munged", "slurmctld", "slurmd"})
        self.cluster.stop()
        for name, pid in pids.items():
            with self.assertRaises(ProcessLookupError, msg=f"{name} ({pid}) still there"):
                os.kill(pid, 0)
        self.assertEqual(sorted(self.cluster.stopped_pids), sorted(pids.values()))
        self.assertEqual(self.cluster.killed_leftovers, [], "job processes outlived the cluster")
        self.assertEqual(self.cluster.leftover_processes(), [])
        self.assertFalse(root.exists())


def main() -> int:
    started = time.monotonic()
    program = unittest.main(exit=False, verbosity=2)
    result = program.result
    if UNAVAILABLE is not None and result.wasSuccessful():
        print(f"SKIP: the loopback Slurm cluster cannot start here: {UNAVAILABLE}")
        return 0
    print(f"{result.testsRun - len(result.failures) - len(result.errors) - len(result.skipped)} "
          f"passed, {len(result.failures) + len(result.errors)} failed "
          f"({time.monotonic() - started:.1f} s)")
    return 0 if result.wasSuccessful() else 1


if __name__ == "__main__":
    sys.exit(main())
