#!/usr/bin/env python3
"""pnb-sweep: one sweep description, expanded into independent jobs with content-addressed results.

A sweep (TOML or JSON, docs/SWEEP.md) names scenes, settings axes and what to measure:

    name = "shadows"
    frames = 30                      # pnb-play --bench --frames
    size = "320x180"
    metrics = { shadow = 15 }        # pnb-play --shadow-metrics 15 (also gi, sky, lod, frame)
    fixed = { "gi.enabled" = "false" }
    [axes]
    "shadows.technique" = ["pssm", "sdsm"]
    "shadows.cascades" = [2, 4]
    [[scenes]]
    name = "street-canyon"
    source = "build/release/scenes/street-canyon.glb"   # a .pnb is played as it is
    convert = ["--sky"]                                  # pnb-convert options for a source
    path = "assets_src/paths/street-canyon.json"         # optional camera path

`axes` may be an array of tables ([[axes]]): the union of each one's combinations. Keys
"convert.OPTION" are pnb-convert options swept like settings ("convert.quantize" = [false, true]).
A file with kind = "command" is a command experiment instead (sweep_command.py): a command line
per combination of its axes, whose job writes named figures; it plans, runs (locally or on Slurm),
collects and reports like a sweep. Every experiment of the repository is a file in
sweep/examples/ (pnb-play sweeps) or sweep/experiments/ (command experiments); scripts/bench-*
run them through `experiment`. Every file is checked against the JSON Schema of its kind
(sweep_schema.py) before anything else reads it: an error names the file, the key and what was
expected. plan, run, experiment, and collect/report --sweep refuse a sweep of more than 1000 jobs
(JOB_LIMIT) unless given --max-jobs N (a larger limit) or --yes (none).

Subcommands:
    plan SWEEP [--results DIR]      the jobs (scene x every combination of the axes), each with its
                                    key: a hash of the scene's bytes and conversion, the settings,
                                    the run options and the binaries' bytes. A job's results live in
                                    DIR/<key>/; a rerun skips jobs whose results are complete, and a
                                    changed axis value, scene or binary reruns only what it changes.
    run --local SWEEP [--results DIR] [-j N] [--gpu-jobs K]
                                    runs the pending jobs on this machine: the conversions they
                                    need first, N at once (cached by their own key), then the
                                    jobs, K at once (default 1: they share the GPU).
    run --slurm SWEEP [--results DIR] [--partition P] [--gres G] [--throttle N] [--wait]
                                    writes the plan into DIR and submits the pending jobs as one
                                    `sbatch --array` job (one task per job, at most N at once,
                                    per-task logs in DIR/slurm/, requeue-friendly: a task only
                                    writes its job's directory, atomically) and a collect job
                                    depending on it (afterany) that writes DIR/results.csv and lists
                                    unfinished jobs in DIR/failed.txt. Run it again to resubmit
                                    exactly the jobs that did not finish.
    run ... --rerun / -- ARGS       --local: runs every job again (a benchmark's new sample);
                                    ARGS: extra arguments for a command experiment (new keys).
    experiment SWEEP [--results DIR] [-o REPORT] [-- ARGS]
                                    run --local --rerun, then the report of those jobs (default
                                    DIR/report): what scripts/bench-* call.
    list [FILE|DIR ...]             every experiment file (default sweep/examples and
                                    sweep/experiments): kind, jobs, what it measures.
    run-job PLAN INDEX              runs one job of a written plan (what a batch scheduler's array
                                    task calls).
    convert (--local | --slurm) INPUTS -o OUTDIR [-- CONVERTER OPTIONS]
                                    batch conversion: INPUTS is a directory (its .gltf, .glb, .obj)
                                    or a file listing one input per line; each becomes
                                    OUTDIR/<stem>.pnb with OUTDIR/<stem>.pnb.inputs recording the
                                    hash of every file the converter read (its depfile), the
                                    options and the converter binary; an output whose record
                                    still matches is skipped. --slurm: one array task per input.
    collect DIR [-o CSV]            one row per finished job: scene, settings, GL renderer, GPU
                                    median per pass, metrics' means, load phases and floor, the
                                    conversion's size and errors.
    budget SCENE (--budget-ms X | --budget-ratio R) [--knobs FILE] [--size WxH] [--frames N]
           [--error METRIC] [--out DIR] [--local | --slurm] [-- CONVERTER OPTIONS]
                                    for one scene and a frame-time budget (ms, or a ratio to the
                                    cheapest starting configuration measured in the same run),
                                    searches the knobs of FILE (default sweep/examples/budget-
                                    knobs.toml: a play sweep whose [[axes]] tables are the knobs)
                                    and prints the configuration with the lowest whole-frame error
                                    within it, the defaults' error and cost, and the front of all
                                    it measured (budget_command.py, budget_search.py); writes
                                    DIR/budget-<scene>.json, which the report shows.
    report DIR -o OUT [--extremes CSV]  OUT/index.html (+ PNGs, results.csv): per scene the Pareto
                                    fronts of each measured error against its cost (per GL
                                    renderer), the GPU time per pass, load time against its floor,
                                    the last measured frames with their error maps; the extremes
                                    table (sweep_report.py; needs matplotlib); command
                                    experiments' figures as tables; an index of every experiment.

Relative paths in a sweep are relative to the sweep file. Binaries come from --build DIR
(default build/release next to this script's repository); jobs with truth metrics are played by
pnb-judge when the build has it (player_for).
"""
import argparse
import csv
import hashlib
import io
import itertools
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib

from sweep_command import (SweepError, collect_row, combination_count, combinations, count_terms, describe,
                           load_command_experiment, plan_command, run_command_job, value_text)
from sweep_schema import validate
from output_guard import check_outputs, write_atomically
from sweep_report import LOAD_PHASES  # pnb-play's load phases, in the order they happen

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
METRIC_FLAGS = {"shadow": "--shadow-metrics", "gi": "--gi-metrics", "sky": "--sky-metrics", "lod": "--lod-metrics",
                "frame": "--frame-metrics"}
# Metrics judged against a ray-traced truth: the ones pnb-judge measures (player_for).
TRUTH_METRICS = {"shadow", "gi", "sky", "frame"}
# The whole frame's path-traced truth costs far more than the frame it judges and does not depend
# on the player's techniques: every job of a results directory shares one cache of them,
# DIR/truth-cache (pnb-judge --frame-truth-cache, whose entries are keyed by what a truth depends
# on: scene, camera, frame, size), so the configurations of one scene pay for it once.
TRUTH_CACHE = "truth-cache"
# Where the experiment files of the repository live: `list` and the report's index read these.
EXPERIMENT_DIRS = [os.path.join(REPO, "sweep", "examples"), os.path.join(REPO, "sweep", "experiments")]
# Axis and fixed keys with this prefix are pnb-convert options, not pnb-play settings:
# "convert.quantize" = [false, true] -> (nothing) | --quantize; "convert.max-texture-size" = [512]
# -> --max-texture-size 512.
CONVERT_PREFIX = "convert."
# Planning more jobs than this needs --max-jobs or --yes: a sweep's jobs multiply, and a stray axis
# (or a value list pasted twice) turns an afternoon's sweep into one that never ends. The largest
# sweep of the repository, sweep/examples/shadows.toml, is 188 jobs.
JOB_LIMIT = 1000


_hashes = {}


def forget_hashes():
    """Files may have changed (a long-lived caller, a test): hash them afresh."""
    _hashes.clear()


def file_hash(path):
    """sha256 of a file's bytes (memoised per process: binaries and scenes are read once)."""
    path = os.path.abspath(path)
    cache = _hashes
    if path not in cache:
        h = hashlib.sha256()
        try:
            with open(path, "rb") as f:
                for block in iter(lambda: f.read(1 << 20), b""):
                    h.update(block)
        except OSError as e:
            raise SweepError("%s: %s" % (path, e.strerror))
        cache[path] = h.hexdigest()
    return cache[path]


def read_json(path):
    with open(path) as f:
        return json.load(f)


def load_sweep(path, check_files=True):
    """A sweep file, checked: its shape against the schema of its kind (sweep_schema.py), then what
    a schema cannot say. check_files=False: scenes and paths need not exist yet (pnb_sweep.py
    list, which only counts the jobs)."""
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f) if path.endswith(".toml") else json.load(f)
    except OSError as e:
        raise SweepError("%s: %s" % (path, e.strerror))
    # Also bytes that are not UTF-8, and arrays nested deeper than the parsers recurse.
    except (tomllib.TOMLDecodeError, json.JSONDecodeError, UnicodeDecodeError, RecursionError) as e:
        raise SweepError("%s: not valid %s: %s" % (path, "TOML" if path.endswith(".toml") else "JSON", e))
    validate(path, data)
    if data.get("kind") == "command":
        try:
            return load_command_experiment(path, data, check_files)
        except ValueError as e:
            raise SweepError(str(e))
    base = os.path.dirname(os.path.abspath(path))
    out_scenes = []
    for i, s in enumerate(data["scenes"]):
        src = os.path.join(base, s["source"])
        if check_files and not os.path.exists(src):
            raise SweepError("%s: scenes[%d].source: %s does not exist" % (path, i, src))
        scene_path = s.get("path")
        if scene_path is not None:
            scene_path = os.path.join(base, scene_path)
            if check_files and not os.path.exists(scene_path):
                raise SweepError("%s: scenes[%d].path: %s does not exist" % (path, i, scene_path))
        out_scenes.append({"name": s.get("name", os.path.splitext(os.path.basename(src))[0]),
                           "source": src, "convert": s.get("convert", []), "path": scene_path})
    # One table: every combination of its axes. An array of tables: the union of each one's
    # combinations (sweeps that are not a full product, e.g. cascades only for some techniques).
    axes = data.get("axes", {})
    groups = axes if isinstance(axes, list) else [axes]
    has_convert = any(k.startswith(CONVERT_PREFIX) for g in groups for k in g) or \
        any(k.startswith(CONVERT_PREFIX) for k in data.get("fixed", {}))
    if has_convert:
        for s in out_scenes:
            if s["source"].endswith(".pnb"):
                raise SweepError("%s: converter axes (%s*) need scenes given by their source, and %s "
                                 "is a container" % (path, CONVERT_PREFIX, s["source"]))
    return {"kind": "play", "name": data.get("name", os.path.splitext(os.path.basename(path))[0]),
            "file": path, "description": describe(path, data),
            "frames": int(data.get("frames", 30)), "size": data.get("size", "320x180"),
            # Whole numbers, as the schema has them, may be written 8.0 (JSON): pnb-play takes "8".
            "metrics": {m: int(every) for m, every in sorted(data.get("metrics", {}).items())},
            "fixed": {k: value_text(v) for k, v in sorted(data.get("fixed", {}).items())},
            "axes": [{k: [value_text(v) for v in vs] for k, vs in g.items()} for g in groups],
            "scenes": out_scenes}


def binaries(build, kind="play"):
    """The tools of a build tree, or of a directory that holds them (an installed bin/). A command
    experiment needs none of them (its `depends` names what it runs): only the directory."""
    if kind == "command":
        return {"build": build}
    flat = not os.path.isdir(os.path.join(build, "player")) and os.path.exists(os.path.join(build, "pnb-play"))
    convert = os.path.join(build, "pnb-convert" if flat else "converter/pnb-convert")
    play = os.path.join(build, "pnb-play" if flat else "player/pnb-play")
    for b in (convert, play):
        if not os.access(b, os.X_OK):
            raise SweepError("%s: not built (cmake --build --preset release --target pnb-convert pnb-play)" % b)
    # pnb-judge: pnb-play with the truth metrics (only jobs that ask for one need it: player_for).
    judge = os.path.join(build, "pnb-judge" if flat else "judge/pnb-judge")
    # The load-time floor (bench/load, not installed): optional, the report says when it is missing.
    probe = os.path.join(build, "bench", "load", "pnb_load_probe")
    return {"build": build, "convert": convert, "play": play,
            "judge": judge if os.access(judge, os.X_OK) else None,
            "probe": probe if os.access(probe, os.X_OK) else None}


def player_for(metrics, bins):
    """The binary that plays a job with these metrics: pnb-judge (pnb-play with the Embree truth)
    when it asks for a truth metric, else the lean pnb-play. The only place that chooses; the
    job's key hashes it."""
    if TRUTH_METRICS & set(metrics):
        if not bins.get("judge"):
            raise SweepError("a truth metric (%s) needs pnb-judge, which this build does not have "
                             "(cmake --build --preset release --target pnb-judge)"
                             % ", ".join(sorted(TRUTH_METRICS & set(metrics))))
        return bins["judge"]
    return bins["play"]


def convert_options(settings):
    """The pnb-convert options a job's convert.* settings stand for, in key order."""
    out = []
    for k, v in sorted(settings.items()):
        if not k.startswith(CONVERT_PREFIX):
            continue
        flag = "--" + k[len(CONVERT_PREFIX):]
        if v == "true":
            out.append(flag)
        elif v != "false":
            out += [flag, v]
    return out


def conversion_key(scene, options, bins):
    """What a converted scene depends on: the source's bytes, the options, the converter."""
    if scene["source"].endswith(".pnb"):
        return None
    h = hashlib.sha256(json.dumps({"source": file_hash(scene["source"]), "convert": options,
                                   "path": file_hash(scene["path"]) if scene["path"] else None,
                                   "converter": file_hash(bins["convert"])}, sort_keys=True).encode())
    return h.hexdigest()


def play_combinations(sweep):
    """The settings of each job of a play sweep (per scene): the fixed settings under every
    combination of each axis group, each once."""
    combos, seen = [], set()
    for group in sweep["axes"]:
        names = list(group.keys())
        for combo in itertools.product(*[group[k] for k in names]):
            settings = dict(sweep["fixed"])
            settings.update(zip(names, combo))
            if tuple(sorted(settings.items())) not in seen:  # groups may overlap
                seen.add(tuple(sorted(settings.items())))
                combos.append(settings)
    return combos


def job_count(sweep):
    """How many jobs a sweep expands into: counted from the sizes of its axes, nothing expanded or
    hashed (`list`, the job limit)."""
    if sweep["kind"] == "command":
        return combination_count(sweep["axes"])
    return len(sweep["scenes"]) * combination_count(sweep["axes"], sweep["fixed"])


def job_count_terms(sweep):
    """How job_count's number arises: "3 scenes x 4 x 2", "3 scenes x (1 + 2 x 4) less 1 shared"."""
    if sweep["kind"] == "command":
        return count_terms(sweep["axes"])
    n = len(sweep["scenes"])
    return "%d scene%s x %s" % (n, "" if n == 1 else "s", count_terms(sweep["axes"], sweep["fixed"]))


def plan(sweep, bins, results, args=(), max_jobs=JOB_LIMIT):
    """The jobs of a sweep with their keys. `args`: extra arguments for a command experiment's
    command (pnb_sweep.py run ... -- ARGS). More than `max_jobs` jobs (None: no limit) is an
    error before any job is made: an axis too many or a stray value multiplies them."""
    n = job_count(sweep)
    if max_jobs is not None and n > max_jobs:
        raise SweepError("%s: %d jobs (%s), more than the limit of %d; to plan them, give --max-jobs %d or --yes"
                         % (sweep["file"], n, job_count_terms(sweep), max_jobs, n))
    if sweep["kind"] == "command":
        jobs = plan_command(sweep, bins["build"], results, args, combinations(sweep["axes"]), file_hash)
        return {"sweep": sweep["name"], "results": results, "binaries": bins, "jobs": jobs}
    if args:
        raise SweepError("%s: arguments after -- are for command experiments (kind = \"command\")" % sweep["name"])
    jobs = plan_jobs(sweep, play_combinations(sweep), bins, results)
    return {"sweep": sweep["name"], "results": results, "binaries": bins, "jobs": jobs}


def plan_jobs(sweep, combos, bins, results, truth_cache=None):
    """The jobs of a play sweep's scenes under each of `combos` (settings dicts), numbered from 0,
    their results in `results`, the frame truth's cache in `truth_cache` (default
    results/truth-cache). What plan expands a sweep into, and what `budget` measures."""
    jobs = []
    for scene in sweep["scenes"]:
        for settings in combos:
            options = scene["convert"] + convert_options(settings)
            ckey = conversion_key(scene, options, bins)
            scene_key = ckey or file_hash(scene["source"])
            player = player_for(sweep["metrics"], bins)
            key = hashlib.sha256(json.dumps({
                "scene": scene_key, "settings": sorted(settings.items()), "frames": sweep["frames"],
                "size": sweep["size"], "metrics": sweep["metrics"], "player": file_hash(player)},
                sort_keys=True).encode()).hexdigest()[:20]
            job = {"index": len(jobs), "key": key, "scene": scene["name"], "source": scene["source"],
                   "player": player,
                   "convert": options, "conversion": ckey, "path": scene["path"],
                   "settings": settings, "frames": sweep["frames"], "size": sweep["size"],
                   "metrics": sweep["metrics"], "result": os.path.join(results, key),
                   "truth_cache": truth_cache or os.path.join(results, TRUTH_CACHE)}
            if "frame" in sweep["metrics"] and convert_options(settings):
                # A lossy conversion (quantised meshes, compressed textures) is judged against the
                # truth of the scene's plain conversion, not of itself (pnb-judge --frame-truth-scene).
                job["truth_convert"] = scene["convert"]
                job["truth_conversion"] = conversion_key(scene, scene["convert"], bins)
            jobs.append(job)
    return jobs


def done(job):
    return os.path.exists(os.path.join(job["result"], "job.json"))


def converted_scene(job, plan_data):
    """The container to play: the source itself, or its conversion (made once, cached by key)."""
    if job["conversion"] is None:
        return job["source"]
    cache = os.path.join(plan_data["results"], "converted")
    os.makedirs(cache, exist_ok=True)
    out = os.path.join(cache, job["conversion"] + ".pnb")
    summary = out + ".summary.json"  # renamed into place last: it marks a finished conversion
    if not (os.path.exists(out) and os.path.exists(summary)):
        # Into a directory of its own: array tasks of one scene may convert it at the same time.
        tmp = tempfile.mkdtemp(prefix=".%s.tmp." % job["conversion"][:12], dir=cache)
        try:
            cmd = [plan_data["binaries"]["convert"], job["source"], "-o", os.path.join(tmp, "scene.pnb"), "-q",
                   "--summary-json", os.path.join(tmp, "summary.json")] + job["convert"]
            if job["path"]:
                cmd += ["--path", job["path"]]
            r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            if r.returncode != 0:
                raise SweepError("conversion failed: %s\n%s" % (" ".join(cmd), r.stdout[-2000:]))
            os.replace(os.path.join(tmp, "scene.pnb"), out)
            os.replace(os.path.join(tmp, "summary.json"), summary)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    return out


def truth_cache(job):
    """Where a job's whole-frame truths are cached (a plan written before the cache had a place:
    beside the job's result)."""
    return job.get("truth_cache") or os.path.join(os.path.dirname(job["result"]), TRUTH_CACHE)


def player_command(job, plan_data, scene, out, truth_scene=None):
    """The pnb-play (or pnb-judge) command line of a play job: the container `scene`, its outputs
    into `out`; `truth_scene`: the container the whole-frame truth is traced from (default: scene)."""
    # The image of the last measured frame (else the last frame): the report's gallery, beside
    # that frame's error maps.
    every = min(job["metrics"].values()) if job["metrics"] else 1
    shot = max(job["frames"] - 1, 0) // every * every
    cmd = [job.get("player") or plan_data["binaries"]["play"], scene, "--headless", "--bench", "--fixed-dt", "--frames",
           str(job["frames"]), "--size", job["size"], "--out", out, "--no-plot", "-q",
           "--screenshot", os.path.join(out, "frame.png"), "--frame", str(shot)]
    for k, v in job["settings"].items():
        if not k.startswith(CONVERT_PREFIX):
            cmd += ["--set", "%s=%s" % (k, v)]
    for m, every in job["metrics"].items():
        cmd += [METRIC_FLAGS[m], str(every)]
    if "frame" in job["metrics"]:
        cmd += ["--frame-truth-cache", truth_cache(job)]
        if truth_scene:
            cmd += ["--frame-truth-scene", truth_scene]
    if job["metrics"]:
        cmd.append("--error-maps")  # beside frame.png in the report's gallery
    return cmd


def run_job(plan_data, index, force=False, echo=False):
    """Runs job `index` of a plan unless it is finished (force: again). echo: a command job's
    output also goes to this process's stdout."""
    job = plan_data["jobs"][index]
    if done(job) and not force:
        return "skipped"
    if job.get("kind") == "command":
        return run_command_job(plan_data, index, echo)
    scene = converted_scene(job, plan_data)
    # Into a temporary directory beside the result, renamed when complete: an interrupted or
    # killed job leaves no result that looks finished.
    parent = os.path.dirname(job["result"])
    os.makedirs(parent, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix=".%s.tmp." % job["key"], dir=parent)
    started = time.time()
    try:
        truth_scene = None
        if job.get("truth_conversion"):
            truth_scene = converted_scene(dict(job, conversion=job["truth_conversion"], convert=job["truth_convert"]),
                                          plan_data)
        cmd = player_command(job, plan_data, scene, tmp, truth_scene)
        if "frame" in job["metrics"]:
            os.makedirs(truth_cache(job), exist_ok=True)
        r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        log = [" ".join(cmd), r.stdout]
        if r.returncode == 0 and plan_data["binaries"].get("probe"):
            # The raw-bytes floor of the load just timed: the same file mapped and copied into
            # fresh memory, right after pnb-play read it (same page-cache state).
            fr = subprocess.run([plan_data["binaries"]["probe"], "--loader", "floor", scene],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            log.append(fr.stdout)
            if fr.returncode == 0:
                with open(os.path.join(tmp, "floor.json"), "w") as f:
                    f.write(fr.stdout.strip().splitlines()[-1] + "\n")
        with open(os.path.join(tmp, "log.txt"), "w") as f:
            f.write("\n".join(log))
        if r.returncode != 0:
            raise SweepError("job %d (%s) failed with exit code %d; log: %s" % (
                index, job["key"], r.returncode, os.path.join(tmp, "log.txt")))
        if job["conversion"] is not None:
            shutil.copyfile(scene + ".summary.json", os.path.join(tmp, "conversion.json"))
        record = {k: job[k] for k in ("index", "key", "scene", "settings", "frames", "size", "metrics")}
        # When and where it ran (wall clock, seconds since the epoch): what a sweep's schedule took.
        record.update(started=started, finished=time.time(), host=os.uname().nodename)
        with open(os.path.join(tmp, "job.json"), "w") as f:
            json.dump(record, f, indent=2, sort_keys=True)
        if os.path.exists(job["result"]):
            shutil.rmtree(job["result"])  # an incomplete earlier attempt
        os.rename(tmp, job["result"])
    except BaseException:
        if os.path.isdir(tmp) and not os.path.exists(os.path.join(tmp, "log.txt")):
            shutil.rmtree(tmp, ignore_errors=True)
        raise
    return "ran"


def run_local(data, pending, jobs, gpu_jobs, force=False):
    """Runs `pending` on this machine: first every conversion they need, `jobs` at once (CPU
    work), then the jobs themselves, `gpu_jobs` at once (default 1: jobs that share a GPU would
    time each other). The first failure stops the run after the jobs in flight; finished jobs
    keep their results."""
    from concurrent.futures import ThreadPoolExecutor

    def each(pool_size, fn, items):
        with ThreadPoolExecutor(max_workers=max(1, pool_size)) as pool:
            futures = [pool.submit(fn, item) for item in items]
            try:
                for f in futures:
                    f.result()
            except BaseException:
                for f in futures:
                    f.cancel()
                raise

    first = {}
    for job in pending:
        if job.get("conversion") is not None:
            first.setdefault(job["conversion"], job)
    each(jobs, lambda job: converted_scene(job, data), list(first.values()))

    def play(job):
        status = run_job(data, job["index"], force, echo=gpu_jobs <= 1)
        print("job %d %s: %s -> %s" % (job["index"], job["key"], status, job["result"]), flush=True)
    # With several jobs at once, the whole-frame truths' first jobs alone first (truth_pilots).
    pilots = truth_pilots(pending) if gpu_jobs > 1 else []
    each(gpu_jobs, play, pilots)
    each(gpu_jobs, play, [j for j in pending if j not in pilots])


def truth_pilots(jobs):
    """Of `jobs`, the first of each group that would path-trace the same whole-frame truths (one
    container, camera path, size, frames and frame interval, one cache): run before the others,
    which then find them cached. Jobs without the frame metric have none."""
    seen, pilots = set(), []
    for j in jobs:
        if "frame" not in j.get("metrics", {}):
            continue
        group = (j.get("truth_conversion") or j.get("conversion") or j["source"], j.get("path"), j["size"],
                 j["frames"], j["metrics"]["frame"],
                 truth_cache(j))
        if group not in seen:
            seen.add(group)
            pilots.append(j)
    return pilots


def slurm_submit(data, a, env=None):
    """Submits the pending jobs of `data` as an array and the dependent collect job. Returns
    (array job id or None, collect job id or None, pending count). With the whole-frame metric,
    the first job of each truth (truth_pilots) goes first as an array of its own, the others'
    array depending on it."""
    results = data["results"]
    pending = [j["index"] for j in data["jobs"] if not done(j)]
    if not pending:
        return None, None, 0
    slurm_dir = os.path.join(results, "slurm")
    os.makedirs(slurm_dir, exist_ok=True)
    plan_file = os.path.join(results, "plan.json")
    with open(plan_file + ".tmp", "w") as f:
        json.dump(data, f, indent=2)
    os.replace(plan_file + ".tmp", plan_file)
    me = os.path.abspath(__file__)
    python = sys.executable
    array = os.path.join(slurm_dir, "array.sh")
    with open(array, "w") as f:
        f.write("#!/bin/sh\n# One pnb-sweep job per array task (pnb_sweep.py run --slurm).\n"
                "exec %s %s run-job %s \"$SLURM_ARRAY_TASK_ID\"\n" % (python, me, plan_file))
    collect_script = os.path.join(slurm_dir, "collect.sh")
    with open(collect_script, "w") as f:
        f.write("#!/bin/sh\n# After the array, finished or not: the table and what is missing.\n"
                "exec %s %s status %s --results %s --write-failed\n" % (python, me, plan_file, results))
    common = ["--parsable", "--chdir", results]
    if a.partition:
        common += ["--partition", a.partition]

    def submit_array(indices, name, after=None):
        spec = ",".join(str(i) for i in indices)
        if a.throttle:
            spec += "%%%d" % a.throttle
        cmd = ["sbatch"] + common + ["--job-name", name, "--array", spec,
                                     "--requeue", "--output", os.path.join(slurm_dir, "%A_%a.out")]
        if a.gres:
            cmd += ["--gres", a.gres]
        if after:
            cmd += ["--dependency", "afterany:" + after]
        r = subprocess.run(cmd + [array], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
        if r.returncode != 0:
            raise SweepError("sbatch failed: %s" % r.stdout.strip())
        return r.stdout.strip().split(";")[0]
    # One job per whole-frame truth first, alone, so that the others find it in the cache
    # instead of all path-tracing it at once.
    pilots = [j["index"] for j in truth_pilots([data["jobs"][i] for i in pending])]
    first = None
    if pilots and len(pilots) < len(pending):
        first = submit_array(pilots, "pnb-sweep-%s-truth" % data["sweep"])
        pending_rest = [i for i in pending if i not in pilots]
    else:
        pending_rest = pending
    array_id = submit_array(pending_rest, "pnb-sweep-" + data["sweep"], first)
    r = subprocess.run(["sbatch"] + common + ["--job-name", "pnb-sweep-collect", "--dependency",
                                              "afterany:" + array_id, "--output",
                                              os.path.join(slurm_dir, "collect_%j.out"), collect_script],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
    if r.returncode != 0:
        raise SweepError("sbatch (collect) failed: %s" % r.stdout.strip())
    return array_id, r.stdout.strip().split(";")[0], len(pending)


def slurm_wait(job_ids, env=None, timeout=3600):
    """Polls squeue until none of `job_ids` is queued or running."""
    end = time.time() + timeout
    while time.time() < end:
        r = subprocess.run(["squeue", "-h", "-o", "%i", "-j", ",".join(job_ids)], stdout=subprocess.PIPE,
                           stderr=subprocess.DEVNULL, text=True, env=env)
        if r.returncode == 0 and not r.stdout.strip():
            return
        time.sleep(1)  # still queued, or squeue failed for a moment (finished ids): ask again
    raise SweepError("jobs %s still queued after %d s" % (",".join(job_ids), timeout))


def conversion_inputs(spec):
    if os.path.isdir(spec):
        return sorted(os.path.join(spec, f) for f in os.listdir(spec)
                      if f.lower().endswith((".gltf", ".glb", ".obj")))
    try:
        with open(spec) as f:
            base = os.path.dirname(os.path.abspath(spec))
            return [os.path.join(base, line.strip()) for line in f if line.strip() and not line.startswith("#")]
    except OSError as e:
        raise SweepError("%s: %s" % (spec, e.strerror))


def conversion_record(inputs_file, options, converter):
    """The record of a conversion: every file read with its hash, the options, the converter."""
    deps = []
    with open(inputs_file) as f:
        text = f.read().replace("\\\n", " ")
    files = text.split(":", 1)[1].split() if ":" in text else []
    for path in sorted(set(files)):
        deps.append([path, file_hash(path) if os.path.exists(path) else None])
    return {"files": deps, "options": options, "converter": file_hash(converter)}


def converted_path(inp, outdir):
    return os.path.join(outdir, os.path.splitext(os.path.basename(inp))[0] + ".pnb")


def up_to_date(inp, outdir, options, converter):
    """Whether `inp`'s output exists and its record still matches every file it was made from."""
    out = converted_path(inp, outdir)
    record_file = out + ".inputs"
    if not (os.path.exists(out) and os.path.exists(record_file)):
        return False
    old = read_json(record_file)
    current = {"files": [[p, file_hash(p) if os.path.exists(p) else None] for p, _ in old["files"]],
               "options": options, "converter": file_hash(converter)}
    return current == old and any(p == os.path.abspath(inp) for p, _ in old["files"])


def convert_one(inp, outdir, options, converter):
    """Converts `inp` unless its recorded inputs still match. Returns 'skipped' or 'converted'."""
    if up_to_date(inp, outdir, options, converter):
        return "skipped"
    out = converted_path(inp, outdir)
    record_file = out + ".inputs"
    os.makedirs(outdir, exist_ok=True)
    depfile = out + ".d.tmp"
    cmd = [converter, inp, "-o", out, "-q", "--depfile", depfile, "-j", "1"] + options
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        raise SweepError("%s: conversion failed (exit %d): %s" % (inp, r.returncode, r.stdout.strip()[-1500:]))
    record = conversion_record(depfile, options, converter)
    os.remove(depfile)
    with open(record_file + ".tmp", "w") as f:
        json.dump(record, f, indent=1)
    os.replace(record_file + ".tmp", record_file)
    return "converted"


def refuse_replacing(inputs, outputs):
    """SweepError when an output is an input or another output (output_guard.py)."""
    message = check_outputs(inputs, outputs)
    if message:
        raise SweepError(message)


def collect(results, keys=None):
    """One row per finished job in `results` (`keys`: only those jobs)."""
    rows = []
    for key in sorted(os.listdir(results)):
        if keys is not None and key not in keys:
            continue
        d = os.path.join(results, key)
        if not os.path.exists(os.path.join(d, "job.json")):
            continue
        job = read_json(os.path.join(d, "job.json"))
        if job.get("kind") == "command":
            rows.append(collect_row(key, job, d))
            continue
        summary = read_json(os.path.join(d, "summary.json"))
        row = {"key": key, "scene": job["scene"], "size": job.get("size", "")}
        for k, v in sorted(job["settings"].items()):
            row["set:" + k] = v
        row["gl_renderer"] = summary.get("gl", {}).get("renderer", "")
        for p, s in sorted(summary.get("gpu_ms", {}).items()):
            row["gpu_ms:" + p] = s.get("median_ms")
        load = summary.get("load_ms", {})
        for p in LOAD_PHASES + ("total",):
            if p in load:
                row["load_ms:" + p] = load[p]
        row["load:file_bytes"] = load.get("file_bytes", "")
        if os.path.exists(os.path.join(d, "floor.json")):
            row["load_ms:floor"] = read_json(os.path.join(d, "floor.json")).get("gpu_ready_ms", "")
        if os.path.exists(os.path.join(d, "conversion.json")):
            conv = read_json(os.path.join(d, "conversion.json"))
            for k in ("output_bytes", "max_position_error", "max_normal_error_deg", "seconds"):
                # An option that was off cost no error: its null is an exact 0 here.
                row["convert:" + k] = conv.get(k) if conv.get(k) is not None else 0
            psnr = conv.get("min_texture_psnr_db")
            # Worst texture's RMSE in 8-bit levels (PSNR = 20 log10(255 / RMSE)); 0: uncompressed.
            row["convert:texture_rmse8"] = 255.0 * 10 ** (-psnr / 20.0) if psnr else 0
        for m, s in sorted(summary.get("quality", {}).items()):
            if isinstance(s, dict) and "mean" in s:
                row["metric:" + m] = s["mean"]
        rows.append(row)
    columns = []
    for r in rows:
        for c in r:
            if c not in columns:
                columns.append(c)
    return columns, rows


def experiment_index(paths):
    """Every experiment file under `paths` (files or directories): path, kind, name, jobs, one line
    of what it measures; a file that does not load has its error instead (scenes need not exist)."""
    files = []
    for p in paths:
        if p in EXPERIMENT_DIRS and not os.path.isdir(p):
            continue  # installed: share/penumbra/sweep has no experiment files
        if os.path.isdir(p):
            files += sorted(os.path.join(p, f) for f in os.listdir(p) if f.endswith((".toml", ".json")))
        else:
            files.append(p)
    out = []
    for f in files:
        e = {"path": os.path.abspath(f), "kind": "", "name": "", "jobs": 0, "description": "", "error": None}
        try:
            sweep = load_sweep(f, check_files=False)
            e.update(kind=sweep["kind"], name=sweep["name"], jobs=job_count(sweep), description=sweep["description"])
        except SweepError as err:
            e["error"] = str(err)
        out.append(e)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(prog="pnb-sweep", description=__doc__.split("\n")[0],
                                 epilog="plan, run, experiment and collect/report --sweep refuse a sweep of more "
                                        "than %d jobs unless given --max-jobs N or --yes" % JOB_LIMIT)
    # Installed, the pnb-sweep wrapper names its own bin/ in PNB_SWEEP_TOOLS.
    ap.add_argument("--build", default=os.environ.get("PNB_SWEEP_TOOLS") or os.path.join(REPO, "build", "release"),
                    help="the build tree (or a directory holding the tools, like an installed bin/) whose "
                         "pnb-convert and pnb-play run the jobs")
    sub = ap.add_subparsers(dest="command", required=True)
    # Every subcommand that plans a sweep's jobs refuses more than a limit of them.
    limit = argparse.ArgumentParser(add_help=False)
    limit.add_argument("--max-jobs", type=int, default=JOB_LIMIT, metavar="N",
                       help="refuse to plan a sweep of more than N jobs (default %d)" % JOB_LIMIT)
    limit.add_argument("--yes", action="store_true", help="plan any number of jobs")
    p = sub.add_parser("plan", parents=[limit])
    p.add_argument("sweep")
    p.add_argument("--results", default=None)
    p.add_argument("-o", "--output", help="write the plan (JSON) here")
    r = sub.add_parser("run", parents=[limit])
    where = r.add_mutually_exclusive_group(required=True)
    where.add_argument("--local", action="store_true", help="run on this machine")
    where.add_argument("--slurm", action="store_true", help="submit to Slurm (sbatch --array)")
    r.add_argument("sweep")
    r.add_argument("--results", default=None)
    r.add_argument("--partition", default=None)
    r.add_argument("--gres", default=None, help="e.g. gpu:1")
    r.add_argument("--throttle", type=int, default=0, help="array tasks running at once (0: no limit)")
    r.add_argument("--wait", action="store_true", help="with --slurm: wait for the array and collect jobs")
    r.add_argument("-j", "--jobs", type=int, default=os.cpu_count() or 1,
                   help="with --local: conversions at once (default: the cores)")
    r.add_argument("--gpu-jobs", type=int, default=1,
                   help="with --local: pnb-play jobs at once (default 1: jobs sharing a GPU time each other)")
    r.add_argument("--rerun", action="store_true",
                   help="with --local: run every job again, finished or not (a benchmark's second sample)")
    ex = sub.add_parser("experiment", parents=[limit],
                        help="run --local --rerun, then report: what scripts/bench-* call")
    ex.add_argument("sweep")
    ex.add_argument("--results", default=None, help="default out/sweep/<name>")
    ex.add_argument("-o", "--output", default=None, help="the report's directory (default RESULTS/report)")
    ls = sub.add_parser("list", help="every experiment file with what it measures")
    ls.add_argument("paths", nargs="*", help="files or directories (default: sweep/examples, sweep/experiments)")
    st = sub.add_parser("status")
    st.add_argument("plan")
    st.add_argument("--results", default=None)
    st.add_argument("--write-failed", action="store_true",
                    help="also write results.csv and failed.txt (the unfinished jobs) into the results")
    j = sub.add_parser("run-job")
    j.add_argument("plan")
    j.add_argument("index", type=int)
    cv = sub.add_parser("convert")
    cwhere = cv.add_mutually_exclusive_group(required=True)
    cwhere.add_argument("--local", action="store_true")
    cwhere.add_argument("--slurm", action="store_true")
    cv.add_argument("inputs")
    cv.add_argument("-o", "--output", required=True)
    cv.add_argument("--partition", default=None)
    cv.add_argument("--wait", action="store_true")
    co = sub.add_parser("convert-one")
    co.add_argument("list")
    co.add_argument("index", type=int)
    c = sub.add_parser("collect", parents=[limit])
    c.add_argument("results")
    c.add_argument("-o", "--output", default=None)
    rp = sub.add_parser("report", parents=[limit])
    rp.add_argument("results")
    for p_ in (c, rp):
        # A results directory keeps every job ever run into it (other sweeps, older binaries).
        p_.add_argument("--sweep", action="append", default=[],
                        help="only the jobs these sweep files plan now, with these binaries (repeatable)")
    rp.add_argument("-o", "--output", required=True)
    rp.add_argument("--extremes", default=None,
                    help="the extremes matrix to include (matrix.csv or its directory; default: the "
                         "build's reference.extremes_matrix output, when it exists)")
    from budget_command import add_arguments as budget_arguments
    budget_arguments(sub.add_parser("budget", help="the settings with the lowest whole-frame error within a "
                                                   "frame-time budget (budget_command.py)"))
    # pnb-convert's own options follow "--" (argparse cannot take them after positionals).
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[:argv.index("--")] if "--" in argv else argv
    a = ap.parse_args(argv)
    a.options = extra
    max_jobs = None if getattr(a, "yes", False) else getattr(a, "max_jobs", None)
    try:
        if a.command == "budget":
            from budget_command import main_budget
            return main_budget(a, binaries(os.path.abspath(a.build)))
        if a.command == "list":
            entries = experiment_index(a.paths or EXPERIMENT_DIRS)
            for e in entries:
                print("%-44s %-7s %5s  %s" % (os.path.relpath(e["path"]), e["kind"],
                                              e["jobs"] if e["error"] is None else "!", e["error"] or e["description"]))
            bad = [e for e in entries if e["error"]]
            print("%d experiment files%s" % (len(entries), ", %d with errors" % len(bad) if bad else ""))
            return 1 if bad else 0
        if a.command == "experiment":
            sweep = load_sweep(a.sweep)
            results = os.path.abspath(a.results or os.path.join("out", "sweep", sweep["name"]))
            data = plan(sweep, binaries(os.path.abspath(a.build), sweep["kind"]), results, extra, max_jobs)
            run_local(data, data["jobs"], os.cpu_count() or 1, 1, force=True)
            from sweep_report import write_report
            columns, rows = collect(results, {j["key"] for j in data["jobs"]})
            try:
                page = write_report(columns, rows, a.output or os.path.join(results, "report"), results, None,
                                    experiment_index(EXPERIMENT_DIRS))
            except RuntimeError as e:
                raise SweepError(str(e))
            print("%s: %d jobs run, results in %s; report: %s" % (sweep["name"], len(data["jobs"]), results, page))
            return 0
        if a.command in ("plan", "run"):
            sweep = load_sweep(a.sweep)
            results = os.path.abspath(a.results or os.path.join("out", "sweep", sweep["name"]))
            data = plan(sweep, binaries(os.path.abspath(a.build), sweep["kind"]), results, extra, max_jobs)
            pending = [job for job in data["jobs"] if not done(job)]
            if a.command == "plan":
                if a.output:
                    refuse_replacing([(a.sweep, "the sweep file")], [(a.output, "the plan (-o)")])
                    write_atomically(a.output, json.dumps(data, indent=2))
                for job in data["jobs"]:
                    print("%3d %s %-8s %-16s %s" % (job["index"], job["key"], "done" if done(job) else "pending",
                                                    job["scene"], " ".join(["%s=%s" % kv for kv in job["settings"].items()]
                                                                           + job.get("args", []))))
                print("%d jobs, %d pending; results in %s" % (len(data["jobs"]), len(pending), results))
                return 0
            if a.slurm:
                if a.rerun:
                    raise SweepError("--rerun is for --local (on Slurm, give another --results)")
                array_id, collect_id, n = slurm_submit(data, a)
                if not n:
                    print("%d jobs, all finished: nothing submitted; results in %s" % (len(data["jobs"]), results))
                    return 0
                print("submitted %d jobs as array %s, collect %s; results in %s" % (n, array_id, collect_id, results))
                if a.wait:
                    slurm_wait([array_id, collect_id])
                    missing = [j for j in data["jobs"] if not done(j)]
                    print("%d of %d jobs finished%s" % (len(data["jobs"]) - len(missing), len(data["jobs"]),
                                                       "; unfinished: see failed.txt" if missing else ""))
                    return 1 if missing else 0
                return 0
            to_run = data["jobs"] if a.rerun else pending
            run_local(data, to_run, a.jobs, a.gpu_jobs, a.rerun)
            print("%d jobs, %d run, results in %s" % (len(data["jobs"]), len(to_run), results))
            return 0
        if a.command == "convert":
            converter = binaries(os.path.abspath(a.build))["convert"]
            inputs = [os.path.abspath(i) for i in conversion_inputs(a.inputs)]
            outdir = os.path.abspath(a.output)
            # Two inputs with one stem would write one file, reported as two; an output may not
            # be an input (an input list that holds .pnb files inside the output directory).
            refuse_replacing([(i, "the input '%s'" % os.path.basename(i)) for i in inputs],
                             [(converted_path(i, outdir), "the output of '%s'" % i) for i in inputs])
            if a.local:
                counts = {"skipped": 0, "converted": 0}
                for inp in inputs:
                    status = convert_one(inp, outdir, a.options, converter)
                    counts[status] += 1
                    print("%s: %s" % (inp, status), flush=True)
                print("%d inputs: %d converted, %d skipped (up to date)" % (len(inputs), counts["converted"],
                                                                           counts["skipped"]))
                return 0
            # Slurm: the inputs whose outputs are stale, one array task each.
            inputs = [i for i in inputs if not up_to_date(i, outdir, a.options, converter)]
            if not inputs:
                print("all outputs up to date: nothing submitted")
                return 0
            os.makedirs(os.path.join(outdir, "slurm"), exist_ok=True)
            job_list = os.path.join(outdir, "slurm", "convert.json")
            with open(job_list, "w") as f:
                json.dump({"inputs": inputs, "output": outdir, "options": a.options, "converter": converter}, f)
            script = os.path.join(outdir, "slurm", "convert.sh")
            with open(script, "w") as f:
                f.write("#!/bin/sh\nexec %s %s convert-one %s \"$SLURM_ARRAY_TASK_ID\"\n"
                        % (sys.executable, os.path.abspath(__file__), job_list))
            cmd = ["sbatch", "--parsable", "--chdir", outdir, "--job-name", "pnb-convert", "--requeue",
                   "--array", "0-%d" % (len(inputs) - 1), "--output", os.path.join(outdir, "slurm", "%A_%a.out")]
            if a.partition:
                cmd += ["--partition", a.partition]
            r = subprocess.run(cmd + [script], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            if r.returncode != 0:
                raise SweepError("sbatch failed: %s" % r.stdout.strip())
            job = r.stdout.strip().split(";")[0]
            print("submitted %d conversions as array %s" % (len(inputs), job))
            if a.wait:
                slurm_wait([job])
            return 0
        if a.command == "convert-one":
            spec = read_json(a.list)
            if not 0 <= a.index < len(spec["inputs"]):
                raise SweepError("%s: no input %d" % (a.list, a.index))
            inp = spec["inputs"][a.index]
            print("%s: %s" % (inp, convert_one(inp, spec["output"], spec["options"], spec["converter"])))
            return 0
        if a.command == "status":
            data = read_json(a.plan)
            missing = [j for j in data["jobs"] if not done(j)]
            for j in missing:
                print("unfinished: job %d %s %s %s" % (j["index"], j["key"], j["scene"],
                                                       " ".join("%s=%s" % kv for kv in j["settings"].items())))
            print("%d of %d jobs finished" % (len(data["jobs"]) - len(missing), len(data["jobs"])))
            if a.write_failed:
                results = a.results or data["results"]
                with open(os.path.join(results, "failed.txt"), "w") as f:
                    for j in missing:
                        f.write("%d %s\n" % (j["index"], j["key"]))
                columns, rows = collect(results)
                if rows:
                    with open(os.path.join(results, "results.csv"), "w", newline="") as f:
                        w = csv.DictWriter(f, fieldnames=columns)
                        w.writeheader()
                        w.writerows(rows)
            return 0
        if a.command == "run-job":
            data = read_json(a.plan)
            if not 0 <= a.index < len(data["jobs"]):
                raise SweepError("%s: no job %d (%d jobs)" % (a.plan, a.index, len(data["jobs"])))
            print("job %d: %s" % (a.index, run_job(data, a.index)))
            return 0
        if a.command in ("collect", "report") and a.sweep:
            a.keys = set()
            for f in a.sweep:
                sweep = load_sweep(f)
                bins = binaries(os.path.abspath(a.build), sweep["kind"])
                a.keys |= {j["key"] for j in plan(sweep, bins, os.path.abspath(a.results), max_jobs=max_jobs)["jobs"]}
        else:
            a.keys = None
        if a.command == "report":
            columns, rows = collect(a.results, a.keys)
            if not rows:
                raise SweepError("%s: no finished jobs to report" % a.results)
            extremes = a.extremes or os.path.join(a.build, "tests", "reference", "extremes")
            if os.path.isdir(extremes):
                extremes = os.path.join(extremes, "matrix.csv")
            if not os.path.exists(extremes):
                if a.extremes:
                    raise SweepError("%s: no extremes matrix (scripts/bench-extremes writes one)" % extremes)
                extremes = None
            try:
                from sweep_report import write_report
                page = write_report(columns, rows, a.output, a.results, extremes, experiment_index(EXPERIMENT_DIRS))
            except RuntimeError as e:
                raise SweepError(str(e))
            print("report: %s (%d configurations)" % (page, len(rows)))
            return 0
        if a.command == "collect":
            columns, rows = collect(a.results, a.keys)
            if a.output:
                refuse_replacing([(f, "the sweep file") for f in (a.sweep or [])],
                                 [(a.output, "the table (-o)")])
            out = io.StringIO() if a.output else sys.stdout
            w = csv.DictWriter(out, fieldnames=columns)
            w.writeheader()
            w.writerows(rows)
            if a.output:
                write_atomically(a.output, out.getvalue())
                print("%d jobs -> %s" % (len(rows), a.output))
            return 0
    except SweepError as e:
        print("pnb-sweep: %s" % e, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
