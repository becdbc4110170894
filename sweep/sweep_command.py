"""pnb-sweep's command experiments (kind = "command", docs/SWEEP.md): a measurement that is not a
pnb-play configuration (a format-read benchmark, the converter against gltfpack, loaders against
assimp, fresh-process start-up, ...) run by the same planner and runners as a sweep, with the same
content-addressed job directories, logs and Slurm arrays. The measurement code stays in bench/; a
job runs one command line with its directory as {out}, and its figures (named numbers) end up in
that directory's figures.json, which collect and report read.

    name = "startup"
    kind = "command"
    description = "pnb-play time to first frame from fresh processes, per cache state"
    command = ["{python}", "{repo}/bench/startup/bench_startup.py", "--build", "{build}", "--out", "{out}"]
    args = []                  # default extra arguments: replaced by those after `--` when given
    depends = ["{repo}/bench/startup/bench_startup.py", "{build}/player/pnb-play"]
    env = { EGL_LOG_LEVEL = "fatal" }
    [figures]                  # unless the command writes {out}/figures.json itself
    file = "startup.csv"       # a glob in the job directory (JSON or CSV)
    label = ["scene", "config", "run"]   # CSV: one figure per row and column, "label:column"
    columns = ["total"]
    # JSON instead: keys = ["ttff_ratio", "runs.*.peak_rss_bytes"]   (dotted paths, * = every key)
    # or a JSON list of records like CSV rows: rows = "results", label = [...], columns = [...]
    [axes]                     # optional: {name} in the command takes each value (one job each)
    scene = ["box-room", "atrium"]
"""
import csv
import fnmatch
import glob
import hashlib
import json
import itertools
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILTIN = ("repo", "build", "out", "python")
PLACEHOLDER = re.compile(r"\{([A-Za-z_][A-Za-z0-9_]*)\}")


class SweepError(Exception):
    """A sweep or experiment that cannot be planned or run; the text names the file or job."""


def value_text(v):
    """A setting value as pnb-play's --set takes it (TOML booleans are true/false)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    return str(v)


def describe(path, data):
    """One line of what an experiment file measures: its `description`, else its first comment."""
    if isinstance(data.get("description"), str):
        return " ".join(data["description"].split())
    try:
        with open(path) as f:
            for line in f:
                line = line.strip()
                if line.startswith("#"):
                    return line.lstrip("#").strip()
                if line:
                    break
    except OSError:
        pass
    return ""


def load_command_experiment(path, data, check_files=True):
    """The description of a command experiment whose shape sweep_schema.py has checked; what the
    schema cannot say (the placeholders it uses) is checked here. ValueError names the file and
    the key."""
    command = data["command"]
    depends = data.get("depends", [])
    env = data.get("env", {})
    axes = data.get("axes", {})
    groups = axes if isinstance(axes, list) else [axes]
    names = set(BUILTIN) | {k for g in groups for k in g}
    for where, texts in (("command", command), ("depends", depends), ("env", list(env.values()))):
        for text in texts:
            for m in PLACEHOLDER.finditer(text):
                if m.group(1) not in names:
                    raise ValueError("%s: %s: unknown placeholder {%s} (known: %s)"
                                     % (path, where, m.group(1), ", ".join(sorted(names))))
    return {"kind": "command", "name": data.get("name", os.path.splitext(os.path.basename(path))[0]),
            "file": path, "description": describe(path, data), "command": command,
            "args": data.get("args", []), "depends": depends, "env": env, "figures": data.get("figures"),
            "axes": [{k: [value_text(v) for v in vs] for k, vs in g.items()} for g in groups]}


def substitute(text, values):
    return PLACEHOLDER.sub(lambda m: values.get(m.group(1), m.group(0)), text)


def plan_command(sweep, build, results, args, combinations, file_hash):
    """One job per combination of the axes (one job without axes). The key: the command as
    written with the axis values in, the extra arguments, the environment and the bytes of every
    file in `depends` (a missing one is an error: not built)."""
    builtin = {"repo": REPO, "build": build, "python": sys.executable}
    args = list(args) or sweep["args"]
    jobs = []
    for settings in combinations:
        depends = {}
        for d in sweep["depends"]:
            p = substitute(d, dict(builtin, **settings))
            if not os.path.exists(p):
                raise SweepError("%s: %s does not exist (depends; not built?)" % (sweep["name"], p))
            depends[d] = file_hash(p)
        key = hashlib.sha256(json.dumps({
            "kind": "command", "name": sweep["name"],
            "command": [substitute(c, settings) for c in sweep["command"]], "args": list(args),
            "env": sweep["env"], "settings": sorted(settings.items()), "depends": depends},
            sort_keys=True).encode()).hexdigest()[:20]
        jobs.append({"index": len(jobs), "key": key, "kind": "command", "scene": sweep["name"],
                     "settings": settings, "command": sweep["command"], "args": list(args),
                     "env": sweep["env"], "figures": sweep["figures"],
                     "result": os.path.join(results, key)})
    return jobs


def _number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return text


def _walk(doc, parts, name, out, source):
    if not parts:
        if isinstance(doc, (dict, list)):
            raise ValueError("%s: %s is not a number or text" % (source, name))
        out[name] = doc
        return
    head, rest = parts[0], parts[1:]
    if isinstance(doc, list):  # a list's items are named by their index
        doc = {str(i): v for i, v in enumerate(doc)}
    if not isinstance(doc, dict):
        raise ValueError("%s: %s: not a table" % (source, name or head))
    keys = [k for k in doc if fnmatch.fnmatchcase(k, head)] if "*" in head else [head]
    if not keys or keys[0] not in doc:
        raise ValueError("%s: no key %s" % (source, ".".join(filter(None, [name, head]))))
    for k in keys:
        _walk(doc[k], rest, ".".join(filter(None, [name, k])), out, source)


def extract_figures(spec, job_dir):
    """The figures the spec names, from the job's own output files."""
    files = sorted(glob.glob(os.path.join(job_dir, spec["file"])))
    if not files:
        raise ValueError("no %s in the job directory" % spec["file"])
    out = {}
    for path in files:
        rel = os.path.relpath(os.path.dirname(path), job_dir)
        prefix = "" if len(files) == 1 else rel + "/"
        source = os.path.relpath(path, job_dir)
        if path.endswith(".csv"):
            with open(path, newline="") as f:
                rows = list(csv.DictReader(f))
            for r in rows:
                missing = [c for c in spec["label"] + spec["columns"] if c not in r]
                if missing:
                    raise ValueError("%s: no column %s" % (source, missing[0]))
                label = ":".join(r[c] for c in spec["label"])
                for c in spec["columns"]:
                    out["%s%s:%s" % (prefix, label, c)] = _number(r[c])
        elif "rows" in spec:  # a JSON list of records, named like CSV rows
            with open(path) as f:
                doc = json.load(f)
            records = doc
            for part in spec["rows"].split("."):
                if not isinstance(records, dict) or part not in records:
                    raise ValueError("%s: no key %s" % (source, spec["rows"]))
                records = records[part]
            if not isinstance(records, list):
                raise ValueError("%s: %s is not a list" % (source, spec["rows"]))
            for i, record in enumerate(records):
                label = []
                for c in spec["label"]:
                    one = {}
                    _walk(record, c.split("."), "", one, "%s: %s[%d]" % (source, spec["rows"], i))
                    label.append(str(next(iter(one.values()))))
                for c in spec["columns"]:
                    one = {}
                    _walk(record, c.split("."), "", one, "%s: %s[%d]" % (source, spec["rows"], i))
                    out.update({"%s%s:%s" % (prefix, ":".join(label), k): v for k, v in one.items()})
        else:
            with open(path) as f:
                doc = json.load(f)
            found = {}
            for k in spec["keys"]:
                _walk(doc, k.split("."), "", found, source)
            out.update({prefix + k: v for k, v in found.items()})
    return out


def check_figures(figures, source):
    if not isinstance(figures, dict) or not all(
            isinstance(k, str) and (v is None or isinstance(v, (int, float, str, bool))) for k, v in figures.items()):
        raise ValueError("%s: must be a JSON object of named numbers (or text)" % source)
    return figures


def run_command_job(plan_data, index, echo=False):
    """Runs a command job in a temporary directory beside its result ({out}), from the
    repository's root, its output teed into log.txt (and to this process's stdout with echo);
    renames the directory into place once its figures are written."""
    job = plan_data["jobs"][index]
    parent = os.path.dirname(job["result"])
    os.makedirs(parent, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix=".%s.tmp." % job["key"], dir=parent)
    values = dict(job["settings"], repo=REPO, build=plan_data["binaries"]["build"], out=tmp,
                  python=sys.executable)
    cmd = [substitute(c, values) for c in job["command"]] + [substitute(a, values) for a in job["args"]]
    env = dict(os.environ, PNB_JOB_DIR=tmp, **{k: substitute(v, values) for k, v in job["env"].items()})
    started = time.time()
    try:
        log_path = os.path.join(tmp, "log.txt")
        with open(log_path, "w") as log:
            log.write(" ".join(cmd) + "\n")
            log.flush()
            try:
                p = subprocess.Popen(cmd, cwd=REPO, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     text=True, errors="replace")
            except OSError as e:
                log.write("cannot start: %s\n" % e)
                raise SweepError("job %d (%s): cannot start %s: %s; log: %s"
                                 % (index, job["key"], cmd[0], e.strerror, log_path))
            with p:
                for line in p.stdout:
                    log.write(line)
                    if echo:
                        sys.stdout.write(line)
                        sys.stdout.flush()
            code = p.wait()
        if code != 0:
            raise SweepError("job %d (%s) failed with exit code %d; log: %s" % (index, job["key"], code, log_path))
        fig_path = os.path.join(tmp, "figures.json")
        try:
            if os.path.exists(fig_path):
                with open(fig_path) as f:
                    figures = check_figures(json.load(f), "figures.json")
            elif job["figures"]:
                figures = extract_figures(job["figures"], tmp)
            else:
                raise ValueError("the command wrote no figures.json and the experiment names no [figures]")
        except (ValueError, OSError) as e:
            raise SweepError("job %d (%s) %s: %s; log: %s" % (index, job["key"], job["scene"], e, log_path))
        with open(fig_path + ".tmp", "w") as f:
            json.dump(figures, f, indent=1, sort_keys=True)
        os.replace(fig_path + ".tmp", fig_path)
        record = {k: job[k] for k in ("index", "key", "kind", "scene", "settings", "args")}
        record.update(command=cmd, started=started, finished=time.time(), host=os.uname().nodename)
        with open(os.path.join(tmp, "job.json"), "w") as f:
            json.dump(record, f, indent=2, sort_keys=True)
        if os.path.exists(job["result"]):
            shutil.rmtree(job["result"])  # an incomplete earlier attempt, or a forced rerun
        os.rename(tmp, job["result"])
    except BaseException:
        if os.path.isdir(tmp) and not os.path.exists(os.path.join(tmp, "log.txt")):
            shutil.rmtree(tmp, ignore_errors=True)
        raise
    return "ran"


def collect_row(key, job, job_dir):
    """A command job's row: its experiment, axis values, extra arguments and figures."""
    with open(os.path.join(job_dir, "figures.json")) as f:
        figures = json.load(f)
    row = {"key": key, "scene": job["scene"], "kind": "command"}
    for k, v in sorted(job["settings"].items()):
        row["set:" + k] = v
    row["args"] = " ".join(job.get("args", []))
    for name, v in figures.items():
        row["fig:" + name] = v
    return row


def combinations(axes):
    """Every combination of each axis group, in order, each once (groups may overlap)."""
    combos, seen = [], set()
    for group in axes:
        names = list(group.keys())
        for combo in itertools.product(*[group[k] for k in names]):
            settings = dict(zip(names, combo))
            if tuple(sorted(settings.items())) not in seen:
                seen.add(tuple(sorted(settings.items())))
                combos.append(settings)
    return combos


def _union_size(boxes):
    """How many settings the union of `boxes` holds (each a dict of key -> set of values, all over
    the same keys): each box's size less what it shares with the boxes before it."""
    total = 0
    for i, box in enumerate(boxes):
        shared = []
        for earlier in boxes[:i]:
            meet = {k: box[k] & earlier[k] for k in box}
            if all(meet.values()) and meet not in shared:
                shared.append(meet)
        total += math.prod(len(values) for values in box.values()) - _union_size(shared)
    return total


def combination_count(axes, fixed=None):
    """len(combinations(axes)), or with `fixed` the number of a play sweep's settings (the fixed
    ones under each combination), from the axes' sizes alone: a sweep of 10^8 jobs is counted,
    not expanded. Groups whose settings have the same keys may share combinations: once each."""
    by_keys = {}
    for group in axes:
        box = {k: frozenset([v]) for k, v in (fixed or {}).items()}
        box.update({k: frozenset(vs) for k, vs in group.items()})
        by_keys.setdefault(frozenset(box), []).append(box)
    return sum(_union_size(boxes) for boxes in by_keys.values())


def count_terms(axes, fixed=None):
    """How combination_count's number arises: "4 x 2" (the distinct values of each axis), for
    several groups "(1 + 2 x 4 + 8)", less the combinations they share."""
    sizes = [[len(set(vs)) for vs in group.values()] for group in axes]
    terms = [" x ".join(str(n) for n in s) or "1" for s in sizes]
    if len(terms) == 1:
        return terms[0]
    shared = sum(math.prod(s) for s in sizes) - combination_count(axes, fixed)
    return "(%s)%s" % (" + ".join(terms), " less %d shared" % shared if shared else "")
