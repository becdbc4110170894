#!/usr/bin/env python3
"""`pnb_sweep.py budget --slurm` on a single-node Slurm cluster started on loopback for the test
(sweep/slurm_cluster.py): each batch of the search (one knob's values, a trade, the
re-measurements) runs as an array of the stand-in pnb-judge of budget_test.py, and the search
gives the answer, the configurations and the verdict the local runner gives from an empty
results directory. Prints "SKIP: <reason>" and exits 0 where the daemons cannot start (CTest
reports the test as skipped). Most of its time is Slurm's scheduling latency.

Usage: budget_slurm_test.py   (no build needed)
"""
import json
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "sweep"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import budget_test  # noqa: E402
from slurm_cluster import ClusterUnavailable, LocalSlurmCluster  # noqa: E402

# Two knobs of two values: few batches, so few rounds of Slurm's latency.
KNOBS = budget_test.KNOBS.replace('"test.a" = [0, 1, 2, 3]', '"test.a" = [0, 3]').replace(
    '[[axes]]\n"test.b" = [0, 1, 2]\n', '')


def answer(results):
    with open(os.path.join(results, "budget-room.json")) as f:
        record = json.load(f)
    return (record["answer"]["settings"], record["answer"]["cost"], record["answer"]["error"],
            sorted(json.dumps(r["settings"], sort_keys=True) for r in record["configurations"]),
            record["verdict"]["advantage_outside_noise"])


def main():
    try:
        with LocalSlurmCluster() as cluster:
            os.environ.update(cluster.env)  # sbatch and squeue see the test's cluster
            t = budget_test.BudgetCommand()
            t.setUp()
            try:
                with open(t.knobs, "w") as f:
                    f.write(KNOBS)
                code, out = t.budget("--budget-ms", "9.5", "--slurm", "--throttle", "2")
                if code != 0:
                    raise AssertionError("budget --slurm: exit %d\n%s" % (code, out))
                on_cluster = answer(t.results)
                if not os.path.isdir(os.path.join(t.results, "slurm")):
                    raise AssertionError("no Slurm array ran: %s" % out)
                t.results = os.path.join(t.dir, "local")
                code, out = t.budget("--budget-ms", "9.5", "--local")
                if code != 0:
                    raise AssertionError("budget --local: exit %d\n%s" % (code, out))
                local = answer(t.results)
                if on_cluster != local:
                    raise AssertionError("Slurm and local searches differ:\n%s\n%s" % (on_cluster, local))
                print("budget --slurm: %s, %d configurations, as the local search" % (
                    on_cluster[0], len(on_cluster[3])))
            finally:
                t.tearDown()
    except ClusterUnavailable as e:
        print("SKIP: %s" % e)
    return 0


if __name__ == "__main__":
    sys.exit(main())
