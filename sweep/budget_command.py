"""`pnb_sweep.py budget`: for a scene and a frame-time budget, the settings with the lowest
whole-frame error within it (issue 40, part 4; docs/SWEEP.md "Settings for a budget").

    sweep/pnb_sweep.py budget SCENE (--budget-ms X | --budget-ratio R) [--knobs FILE.toml]
        [--size WxH] [--frames N] [--error METRIC] [--out DIR] [--local | --slurm ...] [-- CONVERT OPTIONS]

The knob space is a play sweep file (default sweep/examples/budget-knobs.toml): each table of its
[[axes]] is one knob whose candidate values are the table's combinations, first the cheapest;
its `fixed` settings hold for every configuration; its frames, size and metrics are the
measurement's unless given here (the `frame` metric is added when missing and the error is one of
the whole frame's; another truth metric's error, like the sun shadows' weighted_error_pct, is
searched the same way with that metric in the knob file). Its scenes are not
used: SCENE is (a .pnb as it is, or a source converted with the options after `--`).
budget_search.py searches; this file measures each configuration as a sweep job (pnb-judge with
--frame-metrics, content-addressed in DIR like any sweep's, so a second search reuses what the
first measured, and `report DIR` shows the jobs and the answer), the cost being the median GPU
ms over the frames (summary.json gpu_ms.total), and at the end measures the defaults and the
winner again, into DIR/repeat/, to say whether the winner's advantage is within noise.
Writes DIR/budget-<scene>.json. Exit 0 with an answer, 3 when nothing measured meets the budget,
1 on an error.
"""
import json
import os
import shutil

import budget_search
from sweep_command import SweepError

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_KNOBS = os.path.join(REPO, "sweep", "examples", "budget-knobs.toml")
NO_ANSWER = 3  # the exit code when no configuration meets the budget
FRAME_ERRORS = ("frame_flip_ldr", "frame_flip_hdr", "frame_relmse")


# The smallest whole-frame FLIP difference the truth resolves: the player's frame_flip_ldr moved by
# 0.0009 when the truth's noise target went from 0.003 (the default) to 0.0003 (box room, 160x90;
# docs/REFERENCE.md "The whole frame in pnb-judge"). A smaller advantage is within noise.
FLIP_TRUTH_RESOLUTION = 0.001

def add_arguments(p):
    p.add_argument("scene", help="a .pnb container, or a source (.glb, .gltf, .obj) converted with the "
                                 "pnb-convert options after --")
    budget = p.add_mutually_exclusive_group(required=True)
    budget.add_argument("--budget-ms", type=float, help="the frame-time budget, GPU ms per frame (median)")
    budget.add_argument("--budget-ratio", type=float,
                        help="the budget as a multiple of the cheaper of the defaults and the floor (every "
                             "knob at its first, cheapest value), both measured first in this run")
    p.add_argument("--ratio-to", choices=("cheapest", "defaults"), default="cheapest",
                   help="--budget-ratio's reference: the cheaper of the defaults and the floor (default), or "
                        "the defaults (--budget-ratio 1 --ratio-to defaults: no slower than the defaults)")
    p.add_argument("--knobs", default=DEFAULT_KNOBS, help="the knob space: a play sweep file whose [[axes]] "
                                                          "tables are the knobs (default %(default)s)")
    p.add_argument("--size", default=None, help="WxH (default: the knob file's)")
    p.add_argument("--frames", type=int, default=None, help="frames per measurement (default: the knob file's)")
    p.add_argument("--frame-every", type=int, default=None,
                   help="measure the whole-frame error every N-th frame (default: the knob file's frame metric)")
    p.add_argument("--error", default="frame_flip_ldr",
                   help="the error minimised: a quality column (default frame_flip_ldr; also frame_flip_hdr, "
                        "frame_relmse)")
    p.add_argument("--name", default=None, help="the scene's name (default: its file's stem)")
    p.add_argument("--path", default=None, help="a camera path for a source scene (pnb-convert --path)")
    p.add_argument("--out", default=None, help="the results directory (default out/sweep/budget)")
    p.add_argument("--max-configs", type=int, default=60, help="measure at most N configurations (default 60)")
    p.add_argument("--trades", type=int, default=4,
                   help="when no single move helps: measure the N pairs of single moves predicted (from "
                        "their own measurements) to lower the error within the budget (default 4)")
    p.add_argument("--pairs", action="store_true",
                   help="when no single knob's move helps, try every pair of knobs at once (knobs that "
                        "interact; many more measurements)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--local", action="store_true", help="measure on this machine (the default)")
    where.add_argument("--slurm", action="store_true",
                       help="measure each batch (one knob's values) as a Slurm array, waiting for it")
    p.add_argument("--partition", default=None)
    p.add_argument("--gres", default=None, help="with --slurm, e.g. gpu:1")
    p.add_argument("--throttle", type=int, default=0, help="with --slurm: array tasks at once (0: no limit)")


class Measurer:
    """Measures configurations of one scene as sweep jobs (budget_search.Search's `measure`)."""

    def __init__(self, sweep, bins, results, error, slurm=None):
        import pnb_sweep
        self.sweep, self.bins, self.results, self.error, self.slurm = sweep, bins, results, error, slurm
        self.player_defaults = None  # the player's settings, from the defaults' summary.json
        self.pnb_sweep = pnb_sweep

    def canonical(self, settings):
        """Settings less those equal to the player's defaults (the sweep's fixed ones stay)."""
        if self.player_defaults is None:
            return dict(settings)
        return {k: v for k, v in settings.items()
                if k in self.sweep["fixed"] or self.player_defaults.get(k) != v}

    def run(self, jobs):
        """Runs `jobs` (numbered from 0); the reason each failed one failed."""
        data = {"sweep": self.sweep["name"], "results": self.results, "binaries": self.bins, "jobs": jobs}
        failed = {}
        if self.slurm is not None:
            if any(not self.pnb_sweep.done(j) for j in jobs):
                # The array's own collect job (results.csv, failed.txt) may finish later: the
                # search reads the jobs' directories.
                array_id, _, _ = self.pnb_sweep.slurm_submit(data, self.slurm)
                self.pnb_sweep.slurm_wait([array_id])
            for j in jobs:
                if not self.pnb_sweep.done(j):
                    failed[j["index"]] = "did not finish (its Slurm log: %s/slurm/)" % self.results
            return failed
        for j in jobs:
            try:
                self.pnb_sweep.run_job(data, j["index"])
            except SweepError as e:
                failed[j["index"]] = str(e)
        return failed

    def read(self, job, failed):
        if job["index"] in failed:
            return {"failed": failed[job["index"]], "key": job["key"]}
        summary = self.pnb_sweep.read_json(os.path.join(job["result"], "summary.json"))
        quality = summary.get("quality", {})
        if self.error not in quality or "mean" not in quality[self.error]:
            return {"failed": "no %s in %s (does this pnb-judge have --frame-metrics?)"
                              % (self.error, os.path.join(job["result"], "summary.json")), "key": job["key"]}
        noise = quality.get("frame_truth_noise_relmse", {}).get("mean")
        if self.player_defaults is None and not set(job["settings"]) - set(self.sweep["fixed"]):
            self.player_defaults = summary.get("settings", {})
        return {"cost": summary["gpu_ms"]["total"]["median_ms"], "error": quality[self.error]["mean"],
                "truth_noise_relmse": noise, "key": job["key"],
                "gl_renderer": summary.get("gl", {}).get("renderer", "")}

    def __call__(self, settings_list):
        jobs = self.pnb_sweep.plan_jobs(self.sweep, settings_list, self.bins, self.results)
        failed = self.run(jobs)
        return [self.read(j, failed) for j in jobs]

    def again(self, settings_list):
        """The same configurations measured again in DIR/repeat/ (an earlier repeat replaced)."""
        repeat = os.path.join(self.results, "repeat")
        jobs = self.pnb_sweep.plan_jobs(self.sweep, settings_list, self.bins, repeat,
                                        truth_cache=os.path.join(self.results, self.pnb_sweep.TRUTH_CACHE))
        for j in jobs:
            shutil.rmtree(j["result"], ignore_errors=True)
        failed = self.run(jobs)
        return [self.read(j, failed) for j in jobs]


def knob_sweep(a, pnb_sweep):
    """The knob file as a sweep of the one scene, with the frame metric; and its knobs."""
    knobs_file = pnb_sweep.load_sweep(a.knobs, check_files=False)
    if knobs_file["kind"] != "play":
        raise SweepError("%s: a knob file is a play sweep file (its [[axes]] tables are the knobs)" % a.knobs)
    scene = os.path.abspath(a.scene)
    if not os.path.exists(scene):
        raise SweepError("%s does not exist" % scene)
    knobs = budget_search.knobs_from_axes(knobs_file["axes"])
    if not knobs or not any(k["values"] for k in knobs):
        raise SweepError("%s: no knobs ([[axes]] tables)" % a.knobs)
    metrics = dict(knobs_file["metrics"])
    # The whole frame's errors need the frame metric; another error (the sun's shadows' weighted
    # error, say) the knob file's metric that writes it.
    if a.frame_every:
        metrics["frame"] = a.frame_every
    if a.error.startswith("frame_"):
        metrics.setdefault("frame", 4)
    if not metrics:
        raise SweepError("%s: no metrics to measure %s with (metrics = { frame = 4 })" % (a.knobs, a.error))
    converts = any(k.startswith(pnb_sweep.CONVERT_PREFIX) for knob in knobs for v in knob["values"] for k in v)
    if converts and scene.endswith(".pnb"):
        raise SweepError("%s: converter knobs (%s*) need scenes given by their source, and %s is a container"
                         % (a.knobs, pnb_sweep.CONVERT_PREFIX, scene))
    name = a.name or os.path.splitext(os.path.basename(scene))[0]
    sweep = {"kind": "play", "name": "budget-" + name, "file": a.knobs, "frames": a.frames or knobs_file["frames"],
             "size": a.size or knobs_file["size"], "metrics": metrics, "fixed": knobs_file["fixed"], "axes": [],
             "scenes": [{"name": name, "source": scene, "convert": list(a.options),
                         "path": os.path.abspath(a.path) if a.path else None}]}
    return sweep, knobs


def print_answer(out, result, verdict, error):
    def line(r):
        return "%8.3f ms  %-10.4g %s" % (r["cost"], r["error"], budget_search.describe(r["settings"]))
    w, d = result["winner"], result["defaults"]
    out("best within the budget: %s" % budget_search.describe(w["settings"]))
    out("  %s %.4g, cost %.3f ms (measured again: %s)" % (error, w["error"], w["cost"], again_text(verdict, "winner")))
    out("defaults: %s %.4g, cost %.3f ms%s (measured again: %s)" % (
        error, d["error"], d["cost"], "" if d["cost"] <= result["budget_ms"] else ", over the budget",
        again_text(verdict, "defaults")))
    out("verdict: %s" % verdict["text"])
    for r in verdict["near_misses"]:
        out("  over the budget within the cost's noise, and more accurate: %s (%.3f ms, %.4g)"
            % (budget_search.describe(r["settings"]), r["cost"], r["error"]))
    if result["defaults_on_front"]:
        out("the defaults are on the front: nothing measured is both cheaper and more accurate")
    out("front of the %d configurations measured (cost, %s, configuration):" % (
        len(result["configurations"]) - len(result["failed"]), error))
    for r in result["front"]:
        out("  " + line(r) + ("   <- best within the budget" if r is w else ""))
    if result["failed"]:
        out("%d configurations failed (see budget json): %s" % (len(result["failed"]), "; ".join(
            budget_search.describe(r["settings"]) for r in result["failed"][:5])))
    if result["stopped_at_limit"]:
        out("the search stopped at --max-configs %d: the answer is the best of those measured" % result["max_configs"])


def again_text(verdict, who):
    return "%.3f ms, %.4g" % (verdict[who + "_again"]["cost"], verdict[who + "_again"]["error"]) \
        if verdict.get(who + "_again") else "failed"


def plain(record):
    return {k: v for k, v in record.items() if k != "choice"} if record else None


def main_budget(a, bins, out=print):
    """The budget command with parsed arguments `a` and the build's binaries, its lines through
    `out`. Returns the exit code."""
    import pnb_sweep
    sweep, knobs = knob_sweep(a, pnb_sweep)
    if a.error in ("frame_truth_noise_relmse",):
        raise SweepError("--error %s is the truth's noise, not an error" % a.error)
    results = os.path.abspath(a.out or os.path.join("out", "sweep", "budget"))
    os.makedirs(results, exist_ok=True)
    pnb_sweep.player_for(sweep["metrics"], bins)  # pnb-judge, or an error saying to build it
    m = Measurer(sweep, bins, results, a.error, a if a.slurm else None)
    scene = sweep["scenes"][0]["name"]
    reference = "the defaults' cost" if a.ratio_to == "defaults" else "the cheaper of the defaults and the floor"
    budget_text = "%.3f ms" % a.budget_ms if a.budget_ms is not None else "%.3g x %s" % (a.budget_ratio, reference)
    out("budget search: %s, %s per frame at %s over %d frames, minimising %s; %d knobs from %s"
        % (scene, budget_text, sweep["size"], sweep["frames"], a.error, len(knobs), os.path.relpath(a.knobs)))
    search = budget_search.Search(knobs, m, budget_ms=a.budget_ms, budget_ratio=a.budget_ratio,
                                  fixed=sweep["fixed"], canonical=m.canonical, max_configs=a.max_configs,
                                  pairs=a.pairs, trades=a.trades, ratio_to=a.ratio_to, log=out)
    record = {"scene": scene, "source": sweep["scenes"][0]["source"], "error": a.error, "size": sweep["size"],
              "frames": sweep["frames"], "metrics": sweep["metrics"], "knobs": knobs, "knob_file": a.knobs,
              "budget_ms": a.budget_ms, "budget_ratio": a.budget_ratio, "ratio_to": a.ratio_to}
    path = os.path.join(results, "budget-%s.json" % scene)
    try:
        result = search.run()
    except budget_search.DefaultsFailed as e:
        raise SweepError(str(e))
    except budget_search.NoConfigurationWithinBudget as e:
        record.update(answer=None, message=str(e), budget_ms=search.budget,
                      configurations=[plain(r) for r in search.order])
        write_json(path, record)
        out("pnb-sweep budget: %s" % e)
        return NO_ANSWER
    # Measured again, interleaved in one batch: the spread of two measurements of each.
    w, d = result["winner"], result["defaults"]
    again = m.again([d["settings"], w["settings"]]) if w is not d else m.again([d["settings"]]) * 2
    verdict = {"text": "not measured again: %s" % "; ".join(r.get("failed", "") for r in again if "failed" in r)}
    if all("failed" not in r for r in again):
        truth = (w.get("truth_noise_relmse") if a.error == "frame_relmse"
                 else FLIP_TRUTH_RESOLUTION if a.error.startswith("frame_flip") else None)
        verdict = budget_search.noise_verdict(w, dict(again[1], settings=w["settings"]), d,
                                              dict(again[0], settings=d["settings"]), truth)
        if again[1]["cost"] > result["budget_ms"]:
            verdict["text"] += "; measured again, the winner costs %.3f ms, over the budget of %.3f ms (%s)" % (
                again[1]["cost"], result["budget_ms"],
                "within the cost's noise" if again[1]["cost"] <= result["budget_ms"] * (1 + verdict["cost_noise_rel"])
                else "beyond the cost's noise")
    verdict["defaults_again"], verdict["winner_again"] = (None if "failed" in r else r for r in again)
    # Over the budget by less than the cost's noise and more accurate: a second measurement might
    # have put them inside, so they are named.
    slack = result["budget_ms"] * (1 + verdict.get("cost_noise_rel", 0.0))
    verdict["near_misses"] = [plain(r) for r in result["configurations"] if "failed" not in r
                              and result["budget_ms"] < r["cost"] <= slack and r["error"] < w["error"]]
    out("budget: %.3f ms%s" % (result["budget_ms"], "" if a.budget_ratio is None else
                               " (%.3g x %.3f ms)" % (a.budget_ratio, result["ratio_reference_ms"])))
    print_answer(out, result, verdict, a.error)
    record.update(answer=plain(w), defaults=plain(d), floor=plain(result["floor"]), budget_ms=result["budget_ms"],
                  ratio_reference_ms=result["ratio_reference_ms"], front=[plain(r) for r in result["front"]],
                  configurations=[plain(r) for r in result["configurations"]], verdict=verdict,
                  stopped_at_limit=result["stopped_at_limit"], defaults_on_front=result["defaults_on_front"])
    write_json(path, record)
    out("written: %s (sweep/pnb_sweep.py report %s -o REPORT shows it)" % (path, results))
    return 0


def write_json(path, data):
    with open(path + ".tmp", "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)
    os.replace(path + ".tmp", path)
