#!/usr/bin/env python3
"""The budget search (issue 40, part 4: sweep/budget_search.py, sweep/budget_command.py) and the
whole-frame metric's wiring in the sweep, without a GPU: the search against oracles of known cost
and error (its answer equals the brute-force optimum of the whole space within the budget:
separable knobs, a budget that needs one knob's saving to pay for another's improvement, knobs
that help only together, a joint knob), the budget ratio's reference, a budget nothing meets, the
measurement limit, every configuration measured once; the Pareto front; the noise verdict; the
schema's `frame` metric; the judge's command line for it (--frame-metrics and one truth cache per
results directory); and the command end to end through pnb_sweep.py with a stand-in pnb-judge
(a script that computes an oracle's cost and error from its --set arguments): its output, exit
codes, the re-measurements, budget-<scene>.json and the report's section.

Usage: budget_test.py   (no build needed)
"""
import inspect
import io
import itertools
import json
import os
import stat
import subprocess
import sys
import tempfile
import unittest
from contextlib import redirect_stdout

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "sweep"))
import budget_search  # noqa: E402
import pnb_sweep  # noqa: E402
import sweep_schema  # noqa: E402
from sweep_command import SweepError  # noqa: E402


# The player's defaults of the oracles' settings (what no --set gives).
DEFAULTS = {"test.a": "2", "test.b": "1", "test.c": "0"}


def separable(s):
    """Cost and error adding up over three knobs: more of a knob costs more and errs less."""
    a, b, c = int(s["test.a"]), int(s["test.b"]), int(s["test.c"])
    return 1.0 + 2.0 * a + 1.5 * b + 3.0 * c, 10.0 / (1 + a) + 4.0 / (1 + b) + (2.0 if c == 0 else 0.5)


def interacting(s):
    """b and c each cost and err more alone, and together remove most of the error (a mode that
    needs another on, like sky visibility from the GI's probes)."""
    a, b, c = int(s["test.a"]), int(s["test.b"]), int(s["test.c"])
    error = 10.0 / (1 + a) + (1.0 if b else 0) + (1.0 if c else 0) + 3.0 - (4.5 if b and c else 0)
    return 1.0 + a + 0.5 * b + 0.5 * c, error


def space(values_a=(0, 1, 2, 3), values_b=(0, 1, 2), values_c=(0, 1)):
    return [{"name": k, "values": [{k: str(v)} for v in vs]}
            for k, vs in (("test.a", values_a), ("test.b", values_b), ("test.c", values_c))]


class Oracle:
    """measure() for budget_search.Search: the oracle's figures of the settings over the
    defaults, counting measurements."""

    def __init__(self, fn):
        self.fn, self.measured = fn, []

    def __call__(self, settings_list):
        out = []
        for s in settings_list:
            self.measured.append(dict(s))
            cost, error = self.fn(dict(DEFAULTS, **s))
            out.append({"cost": cost, "error": error})
        return out


def canonical(settings):
    return {k: v for k, v in settings.items() if DEFAULTS.get(k) != v}


def brute_force(fn, knobs, budget):
    """The lowest (error, cost) within the budget over every configuration of the space."""
    best = None
    for combo in itertools.product(*[[None] + k["values"] for k in knobs]):
        s = {}
        for v in combo:
            s.update(v or {})
        cost, error = fn(dict(DEFAULTS, **s))
        if cost <= budget and (best is None or (error, cost) < best[:2]):
            best = (error, cost, canonical(s))
    return best


def search(fn, knobs=None, **kw):
    oracle = Oracle(fn)
    s = budget_search.Search(knobs or space(), oracle, canonical=canonical, **kw)
    return s, s.run(), oracle


class BudgetSearch(unittest.TestCase):
    def test_finds_the_brute_force_optimum_of_separable_knobs_at_every_budget(self):
        knobs = space()
        for budget in (6.0, 8.0, 9.5, 11.0, 14.0, 20.0):
            _, result, oracle = search(separable, budget_ms=budget)
            error, cost, settings = brute_force(separable, knobs, budget)
            self.assertEqual(canonical(result["winner"]["settings"]), settings, "budget %g" % budget)
            self.assertAlmostEqual(result["winner"]["error"], error)
            self.assertLessEqual(result["winner"]["cost"], budget)
            # Each configuration measured once, and fewer than the whole space (4 x 3 x 2 + defaults).
            keys = [tuple(sorted(s.items())) for s in oracle.measured]
            self.assertEqual(len(keys), len(set(keys)))
            self.assertLess(len(keys), 5 * 4 * 3)

    def test_a_trade_pays_for_one_knobs_improvement_with_anothers_saving(self):
        # At 9.5 ms the descent from the defaults (a=2, b=1: 6.5 ms) takes c=1 (9.5 ms) and then
        # no single move fits; the optimum needs a knob moved down to pay for another moved up.
        knobs = space()
        _, result, _ = search(separable, budget_ms=9.5, trades=0)
        without = result["winner"]["error"]
        _, result, _ = search(separable, budget_ms=9.5)
        error, _, _ = brute_force(separable, knobs, 9.5)
        self.assertAlmostEqual(result["winner"]["error"], error)
        self.assertGreater(without, error, "without trades the descent stops short (the test means something)")

    def test_knobs_that_help_only_together_need_pair_moves(self):
        knobs = space(values_b=(0, 1), values_c=(0, 1))
        error, _, settings = brute_force(interacting, knobs, 100.0)
        _, single, _ = search(interacting, knobs, budget_ms=100.0)
        self.assertGreater(single["winner"]["error"], error + 1.0, "neither b nor c helps alone")
        _, paired, _ = search(interacting, knobs, budget_ms=100.0, pairs=True)
        self.assertEqual(canonical(paired["winner"]["settings"]), settings)
        self.assertEqual(settings["test.c"], "1")
        # Or declared as one joint knob (a sweep file's [[axes]] table of both keys).
        joint = budget_search.knobs_from_axes([{"test.a": ["0", "1", "2", "3"]},
                                               {"test.b": ["0", "1"], "test.c": ["0", "1"]}])
        self.assertEqual([k["name"] for k in joint], ["test.a", "test.b+test.c"])
        self.assertEqual(len(joint[1]["values"]), 4)
        _, result, _ = search(interacting, joint, budget_ms=100.0)
        self.assertEqual(canonical(result["winner"]["settings"]), settings)

    def test_budget_ratio_is_to_the_cheaper_start_measured_first(self):
        # The floor (every knob's first value: a=0, b=0, c=0) costs 1 ms, the defaults 6.5 ms.
        s, result, oracle = search(separable, budget_ratio=4.0)
        self.assertEqual(oracle.measured[0], {}, "the defaults first")
        self.assertEqual(oracle.measured[1], {"test.a": "0", "test.b": "0"}, "then the floor")
        self.assertAlmostEqual(result["ratio_reference_ms"], 1.0)
        self.assertAlmostEqual(result["budget_ms"], 4.0)
        self.assertTrue(all(r["cost"] <= 4.0 for r in [result["winner"]]))
        error, _, settings = brute_force(separable, space(), 4.0)
        self.assertAlmostEqual(result["winner"]["error"], error)
        self.assertEqual(budget_search.resolve_budget(None, 1.5, [12.0, None]), 18.0)
        self.assertEqual(budget_search.resolve_budget(7.0, None, [12.0, 3.0]), 7.0)
        self.assertEqual(budget_search.resolve_budget(None, 1.0, [12.0, 3.0], "defaults"), 12.0)
        # No slower than the defaults: the answer beats them or they are on the front.
        _, result, _ = search(separable, budget_ratio=1.0, ratio_to="defaults")
        self.assertAlmostEqual(result["budget_ms"], 6.5)
        self.assertLessEqual(result["winner"]["cost"], 6.5)
        self.assertAlmostEqual(result["winner"]["error"], brute_force(separable, space(), 6.5)[0])
        self.assertTrue(result["winner"]["error"] < result["defaults"]["error"] or result["defaults_on_front"])
        with self.assertRaises(budget_search.NoConfigurationWithinBudget):
            budget_search.resolve_budget(None, 1.5, [None, None])

    def test_a_budget_nothing_meets_says_what_was_cheapest(self):
        with self.assertRaises(budget_search.NoConfigurationWithinBudget) as e:
            search(separable, budget_ms=0.5)
        self.assertIn("no configuration meets the budget of 0.500 ms", str(e.exception))
        self.assertIn("test.a=0 test.b=0", str(e.exception))
        self.assertIn("costs 1.000 ms", str(e.exception))
        with self.assertRaises(ValueError):
            budget_search.Search(space(), Oracle(separable), budget_ms=1.0, budget_ratio=2.0)

    def test_failed_configurations_are_kept_and_never_chosen(self):
        def fails_at_a3(s):
            if s["test.a"] == "3":
                raise KeyError
            return separable(s)

        def measure(settings_list):
            out = []
            for s in settings_list:
                try:
                    cost, error = fails_at_a3(dict(DEFAULTS, **s))
                    out.append({"cost": cost, "error": error})
                except KeyError:
                    out.append({"failed": "exit code 1"})
            return out
        result = budget_search.Search(space(), measure, budget_ms=50.0, canonical=canonical).run()
        self.assertTrue(result["failed"])
        self.assertNotEqual(result["winner"]["settings"].get("test.a"), "3")
        self.assertNotIn(result["winner"], result["failed"])

    def test_the_measurement_limit_stops_the_search(self):
        s, result, oracle = search(separable, budget_ms=20.0, max_configs=5)
        self.assertEqual(len(oracle.measured), 5)
        self.assertTrue(result["stopped_at_limit"])
        self.assertEqual(len(result["configurations"]), 5)

    def test_pareto_front(self):
        points = [(3.0, 1.0), (1.0, 5.0), (2.0, 2.0), (2.5, 2.0), (4.0, 1.0), (1.0, 6.0), (0.5, 9.0)]
        self.assertEqual(budget_search.pareto_front(points), [6, 1, 2, 0])
        self.assertEqual(budget_search.pareto_front([]), [])
        _, result, _ = search(separable, budget_ms=20.0)
        front = result["front"]
        self.assertEqual([r["cost"] for r in front], sorted(r["cost"] for r in front))
        self.assertEqual([r["error"] for r in front], sorted((r["error"] for r in front), reverse=True))
        for r in result["configurations"]:  # nothing measured beats a point of the front in both
            for f in front:
                self.assertFalse(r["cost"] < f["cost"] and r["error"] < f["error"])

    def test_noise_verdict(self):
        d = {"settings": {}, "cost": 10.0, "error": 0.30}
        w = {"settings": {"test.a": "3"}, "cost": 9.0, "error": 0.20}
        v = budget_search.noise_verdict(w, dict(w, cost=9.4, error=0.201), d, dict(d, cost=10.2, error=0.30))
        self.assertTrue(v["advantage_outside_noise"])
        self.assertTrue(v["no_slower_than_defaults"])
        self.assertIn("outside noise", v["text"])
        # The truth's own noise larger than the advantage: within noise.
        v = budget_search.noise_verdict(w, w, d, d, truth_noise=0.2)
        self.assertFalse(v["advantage_outside_noise"])
        self.assertIn("within noise", v["text"])
        # Dearer than the defaults by more than the repeats' spread: slower.
        v = budget_search.noise_verdict(dict(w, cost=12.0), dict(w, cost=12.1), d, dict(d, cost=10.1))
        self.assertFalse(v["no_slower_than_defaults"])
        v = budget_search.noise_verdict(d, d, d, d)
        self.assertIn("the defaults are the best", v["text"])


class FrameMetricWiring(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="pnb_budget_test_")

    def tearDown(self):
        subprocess.run(["rm", "-rf", self.dir])

    def test_the_schema_takes_the_frame_metric(self):
        sweep_schema.validate("ok.toml", {"metrics": {"frame": 4, "shadow": 8}, "scenes": [{"source": "x.pnb"}]})
        for bad, said in (({"frame": 0}, ">= 1"), ({"frame": "4"}, "a frame interval"), ({"frame": 2.5}, "whole"),
                          ({"frames": 4}, "unknown key 'metrics.frames'")):
            with self.assertRaises(SweepError) as e:
                sweep_schema.validate("bad.toml", {"metrics": bad, "scenes": [{"source": "x.pnb"}]})
            self.assertIn(said, str(e.exception))
            self.assertIn("bad.toml", str(e.exception))
        self.assertEqual(pnb_sweep.METRIC_FLAGS["frame"], "--frame-metrics")

    def test_the_judge_gets_the_frame_metric_and_one_truth_cache_per_results_directory(self):
        for name in ("pnb-play", "pnb-judge", "pnb-convert", "scene.pnb"):
            with open(os.path.join(self.dir, name), "w") as f:
                f.write(name)
        bins = {"play": os.path.join(self.dir, "pnb-play"), "judge": os.path.join(self.dir, "pnb-judge"),
                "convert": os.path.join(self.dir, "pnb-convert")}
        results = os.path.join(self.dir, "results")
        sweep = {"kind": "play", "name": "t", "frames": 8, "size": "240x135", "metrics": {"frame": 4},
                 "fixed": {}, "axes": [], "scenes": [{"name": "s", "source": os.path.join(self.dir, "scene.pnb"),
                                                      "convert": [], "path": None}]}
        jobs = pnb_sweep.plan_jobs(sweep, [{"shadows.technique": "sdsm"}, {"lod.threshold_px": "4"}], bins, results)
        self.assertEqual(len({j["key"] for j in jobs}), 2)
        cmds = [pnb_sweep.player_command(j, {"binaries": bins}, j["source"], os.path.join(self.dir, "o"))
                for j in jobs]
        cache = os.path.join(results, "truth-cache")
        for cmd in cmds:
            self.assertEqual(cmd[0], bins["judge"], "the frame's truth is the judge's")
            self.assertEqual(cmd[cmd.index("--frame-metrics") + 1], "4")
            self.assertEqual(cmd[cmd.index("--frame-truth-cache") + 1], cache, "one cache for every job")
            self.assertIn("--error-maps", cmd)
        self.assertIn("--set", cmds[0])
        self.assertEqual(cmds[0][cmds[0].index("--set") + 1], "shadows.technique=sdsm")
        # The cache is not part of the key: the same job planned into another directory keeps it.
        again = pnb_sweep.plan_jobs(sweep, [{"shadows.technique": "sdsm"}], bins, os.path.join(self.dir, "r2"))
        self.assertEqual(again[0]["key"], jobs[0]["key"])
        # One job per truth goes first (truth_pilots): here both share one, the first.
        self.assertEqual(pnb_sweep.truth_pilots(jobs), jobs[:1])
        other_size = pnb_sweep.plan_jobs(dict(sweep, size="64x36"), [{}], bins, results)
        self.assertEqual(pnb_sweep.truth_pilots(jobs + other_size), [jobs[0], other_size[0]])
        # On Slurm, as an array of its own that the others' array waits for (a stand-in sbatch).
        log = os.path.join(self.dir, "sbatch.log")
        with open(os.path.join(self.dir, "sbatch"), "w") as f:
            f.write("#!/bin/sh\necho \"$@\" >> %s\necho $(wc -l < %s)\n" % (log, log))
        os.chmod(os.path.join(self.dir, "sbatch"), 0o755)
        data = {"sweep": "t", "results": results, "binaries": bins, "jobs": jobs + [dict(other_size[0], index=2)]}
        args = type("A", (), {"partition": None, "gres": None, "throttle": 0})
        env = dict(os.environ, PATH=self.dir + os.pathsep + os.environ["PATH"])
        array_id, collect_id, n = pnb_sweep.slurm_submit(data, args, env)
        with open(log) as f:
            calls = f.read().splitlines()
        self.assertEqual((array_id, collect_id, n), ("2", "3", 3))
        self.assertIn("--job-name pnb-sweep-t-truth --array 0,2 ", calls[0])
        self.assertIn("--array 1 ", calls[1])
        self.assertIn("--dependency afterany:1", calls[1])
        self.assertIn("--dependency afterany:2", calls[2])
        # Without the frame metric, no cache.
        sweep["metrics"] = {"shadow": 8}
        job = pnb_sweep.plan_jobs(sweep, [{}], bins, results)[0]
        self.assertNotIn("--frame-truth-cache", pnb_sweep.player_command(job, {"binaries": bins}, "x", "o"))


    def test_a_lossy_conversion_is_judged_against_the_plain_conversions_truth(self):
        for name in ("pnb-play", "pnb-judge", "pnb-convert", "scene.glb"):
            with open(os.path.join(self.dir, name), "w") as f:
                f.write(name)
        bins = {"play": os.path.join(self.dir, "pnb-play"), "judge": os.path.join(self.dir, "pnb-judge"),
                "convert": os.path.join(self.dir, "pnb-convert")}
        results = os.path.join(self.dir, "results")
        sweep = {"kind": "play", "name": "t", "frames": 8, "size": "64x36", "metrics": {"frame": 4},
                 "fixed": {}, "axes": [], "scenes": [{"name": "s", "source": os.path.join(self.dir, "scene.glb"),
                                                      "convert": ["--gi"], "path": None}]}
        plain, quantised = pnb_sweep.plan_jobs(sweep, [{}, {"convert.quantize": "true"}], bins, results)
        self.assertNotIn("truth_conversion", plain, "a player knob's truth is its own container's")
        self.assertEqual(quantised["convert"], ["--gi", "--quantize"])
        self.assertEqual(quantised["truth_convert"], ["--gi"])
        self.assertEqual(quantised["truth_conversion"], plain["conversion"],
                         "the quantised container's truth is the plain conversion's")
        cmd = pnb_sweep.player_command(quantised, {"binaries": bins}, "q.pnb", "o", truth_scene="plain.pnb")
        self.assertEqual(cmd[cmd.index("--frame-truth-scene") + 1], "plain.pnb")
        # Both share one truth: the plain job goes first, the quantised one finds it cached.
        self.assertEqual(pnb_sweep.truth_pilots([plain, quantised]), [plain])


# A stand-in pnb-judge: the oracle's cost and error from its --set arguments, into the
# summary.json pnb-judge writes (settings, gpu_ms, quality), the truth cache marked.
FAKE_JUDGE = '''#!%s
import json, os, sys
DEFAULTS = %r
%s
args = sys.argv[1:]
out = args[args.index("--out") + 1]
settings = dict(DEFAULTS)
for i, a in enumerate(args):
    if a == "--set":
        k, v = args[i + 1].split("=", 1)
        settings[k] = v
if os.environ.get("FAKE_JUDGE_FAIL") and settings["test.a"] == os.environ["FAKE_JUDGE_FAIL"]:
    sys.exit(3)
cost, error = %s(settings)
if os.environ.get("FAKE_JUDGE_REPEAT_SLOWER") and "/repeat/" in out:
    cost *= float(os.environ["FAKE_JUDGE_REPEAT_SLOWER"])
cache = args[args.index("--frame-truth-cache") + 1]
with open(os.path.join(cache, "truths.txt"), "a") as f:
    f.write(out + "\\n")
json.dump({"settings": settings, "gl": {"renderer": "oracle"}, "gpu_ms": {"total": {"median_ms": cost}},
           "load_ms": {}, "quality": {"frame_flip_ldr": {"mean": error}, "frame_relmse": {"mean": error / 10},
                                      "frame_flip_hdr": {"mean": error / 2},
                                      "frame_truth_noise_relmse": {"mean": 0.001}}},
          open(os.path.join(out, "summary.json"), "w"))
'''

KNOBS = '''
name = "oracle-knobs"
description = "the oracle's knob space"
frames = 4
size = "64x36"
metrics = { frame = 2 }
[[axes]]
"test.a" = [0, 1, 2, 3]
[[axes]]
"test.b" = [0, 1, 2]
[[axes]]
"test.c" = [0, 1]
[[scenes]]
source = "unused.glb"
'''


class BudgetCommand(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="pnb_budget_cmd_test_")
        for name in ("pnb-play", "pnb-convert"):
            self.executable(name, "#!/bin/sh\nexit 1\n")
        self.executable("pnb-judge", FAKE_JUDGE % (sys.executable, DEFAULTS, inspect.getsource(separable),
                                                   "separable"))
        self.scene = os.path.join(self.dir, "room.pnb")
        with open(self.scene, "w") as f:
            f.write("a container")
        self.knobs = os.path.join(self.dir, "knobs.toml")
        with open(self.knobs, "w") as f:
            f.write(KNOBS)
        self.results = os.path.join(self.dir, "results")

    def tearDown(self):
        subprocess.run(["rm", "-rf", self.dir])

    def executable(self, name, text):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(text)
        os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR)

    def budget(self, *args):
        out, err = io.StringIO(), io.StringIO()
        with redirect_stdout(out):
            from contextlib import redirect_stderr
            with redirect_stderr(err):
                code = pnb_sweep.main(["--build", self.dir, "budget", self.scene, "--knobs", self.knobs,
                                       "--out", self.results] + list(args))
        return code, out.getvalue() + err.getvalue()

    def test_the_command_answers_remeasures_and_the_report_shows_it(self):
        code, out = self.budget("--budget-ms", "9.5")
        self.assertEqual(code, 0, out)
        error, cost, settings = brute_force(separable, space(), 9.5)
        self.assertIn("best within the budget: %s" % budget_search.describe(settings), out)
        self.assertIn("frame_flip_ldr %.4g, cost %.3f ms" % (error, cost), out)
        self.assertIn("defaults: frame_flip_ldr %.4g, cost 6.500 ms" % separable(DEFAULTS)[1], out)
        self.assertIn("outside noise", out)
        self.assertIn("front of the", out)
        self.assertNotIn("over the budget within the cost's noise", out, "the stand-in's costs do not move")
        with open(os.path.join(self.results, "budget-room.json")) as f:
            record = json.load(f)
        self.assertEqual(record["answer"]["settings"], settings)
        self.assertEqual(record["budget_ms"], 9.5)
        self.assertEqual(record["verdict"]["winner_again"]["cost"], cost)
        # Every configuration a finished sweep job, the repeats apart; one truth cache for all.
        columns, rows = pnb_sweep.collect(self.results)
        self.assertEqual(len(rows), len(record["configurations"]))
        self.assertIn("metric:frame_flip_ldr", columns)
        self.assertEqual(len(os.listdir(os.path.join(self.results, "repeat"))), 2)
        with open(os.path.join(self.results, "truth-cache", "truths.txt")) as f:
            self.assertEqual(len(f.read().splitlines()), len(rows) + 2)
        # A second search reuses every job measured (content-addressed): only the repeats run.
        code, out2 = self.budget("--budget-ms", "9.5")
        self.assertEqual(code, 0, out2)
        with open(os.path.join(self.results, "truth-cache", "truths.txt")) as f:
            self.assertEqual(len(f.read().splitlines()), len(rows) + 4)
        report = os.path.join(self.dir, "report")
        self.assertEqual(pnb_sweep.main(["--build", self.dir, "report", self.results, "-o", report]), 0)
        with open(os.path.join(report, "index.html")) as f:
            page = f.read()
        self.assertIn("Budget search: room", page)
        self.assertIn(budget_search.describe(settings), page)
        self.assertTrue(os.path.getsize(os.path.join(report, "budget_room.png")) > 1000)
        # The whole-frame fronts, the truth's noise beside the relative MSE.
        self.assertIn("whole frame: LDR-FLIP of the displayed image", page)
        self.assertIn("truth&#x27;s noise (relMSE)", page)
        self.assertIn("<td>0.001</td>", page)

    def test_ratio_budget_and_a_budget_nothing_meets(self):
        code, out = self.budget("--budget-ratio", "4")
        self.assertEqual(code, 0, out)
        self.assertIn("budget: 4.000 ms (4 x 1.000 ms)", out)
        code, out = self.budget("--budget-ms", "0.5")
        self.assertEqual(code, 3, out)
        self.assertIn("no configuration meets the budget of 0.500 ms", out)
        with open(os.path.join(self.results, "budget-room.json")) as f:
            self.assertIsNone(json.load(f)["answer"])
        report = os.path.join(self.dir, "report")
        self.assertEqual(pnb_sweep.main(["--build", self.dir, "report", self.results, "-o", report]), 0)
        with open(os.path.join(report, "index.html")) as f:
            self.assertIn("No answer:", f.read())

    def test_noisy_repeats_name_the_near_misses(self):
        # Measured again, everything costs 20 % more: a cost noise of 18 %, within which
        # configurations over the budget and more accurate than the answer are named.
        os.environ["FAKE_JUDGE_REPEAT_SLOWER"] = "1.2"
        try:
            code, out = self.budget("--budget-ms", "11.5")
        finally:
            del os.environ["FAKE_JUDGE_REPEAT_SLOWER"]
        self.assertEqual(code, 0, out)
        with open(os.path.join(self.results, "budget-room.json")) as f:
            record = json.load(f)
        verdict = record["verdict"]
        self.assertAlmostEqual(verdict["cost_noise_rel"], 0.2 / 1.1)
        self.assertIn("measured again, the winner costs", verdict["text"])
        near = verdict["near_misses"]
        self.assertTrue(near)
        for r in near:
            self.assertTrue(11.5 < r["cost"] <= 11.5 * (1 + 0.2 / 1.1) and r["error"] < record["answer"]["error"])
            self.assertIn("over the budget within the cost's noise, and more accurate: %s"
                          % budget_search.describe(r["settings"]), out)
        report = os.path.join(self.dir, "report")
        self.assertEqual(pnb_sweep.main(["--build", self.dir, "report", self.results, "-o", report]), 0)
        with open(os.path.join(report, "index.html")) as f:
            self.assertIn("Over the budget within the cost's noise, and more accurate: %s"
                          % budget_search.describe(near[0]["settings"]), f.read())

    def test_failing_configurations_and_bad_arguments(self):
        os.environ["FAKE_JUDGE_FAIL"] = "3"
        try:
            code, out = self.budget("--budget-ms", "50")
        finally:
            del os.environ["FAKE_JUDGE_FAIL"]
        self.assertEqual(code, 0, out)
        self.assertIn("configurations failed", out)
        with open(os.path.join(self.results, "budget-room.json")) as f:
            self.assertNotEqual(json.load(f)["answer"]["settings"].get("test.a"), "3")
        code, out = self.budget("--budget-ms", "9", "--error", "frame_nothing")
        self.assertEqual(code, 1, out)
        self.assertIn("the defaults could not be measured", out)
        self.assertIn("no frame_nothing in", out)
        with open(self.knobs, "a") as f:
            f.write('[[axes]]\n"convert.quantize" = [true]\n')
        code, out = self.budget("--budget-ms", "9")
        self.assertEqual(code, 1)
        self.assertIn("converter knobs (convert.*) need scenes given by their source, and %s" % self.scene, out)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
