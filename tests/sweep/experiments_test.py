#!/usr/bin/env python3
"""pnb-sweep's experiment files and command experiments (docs/SWEEP.md, "Command experiments"):
every experiment file in the repository loads and expands into jobs, `list` and the report's
index name every one; a command experiment's jobs run by the local runner with their figures
(written by the command, or taken from its JSON or CSV by [figures]) collected and shown in the
report; a failed or figure-less command leaves no finished job; reruns, --rerun and extra
arguments; bad command experiments name the file and the key; the player binary's choice.

Usage: experiments_test.py   (no build needed: the commands are Python one-liners)
"""
import glob
import io
import json
import os
import subprocess
import sys
import tempfile
import unittest
from contextlib import redirect_stdout

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "sweep"))
import pnb_sweep  # noqa: E402

# A command that writes its figures itself: n, twice n and how many extra arguments it got.
WRITES_FIGURES = """
name = "tiny-command"
kind = "command"
description = "a tiny command writing its own figures"
command = ["{python}", "-c", "import json, sys; json.dump({'n': {n}, 'twice': 2 * {n}, 'nargs': len(sys.argv) - 1}, open('{out}/figures.json', 'w')); print('measured {n}')"]
[axes]
n = [1, 2, 3]
"""


class Experiments(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="pnb_experiments_test_")
        self.results = os.path.join(self.dir, "results")

    def tearDown(self):
        subprocess.run(["rm", "-rf", self.dir])

    def write(self, name, text):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def sweep(self, *args):
        out = io.StringIO()
        with redirect_stdout(out):
            code = pnb_sweep.main(["--build", self.dir] + list(args))
        return code, out.getvalue()

    def test_every_experiment_file_loads_expands_and_is_listed(self):
        files = sorted(glob.glob(os.path.join(REPO, "sweep", "examples", "*.toml")) +
                       glob.glob(os.path.join(REPO, "sweep", "experiments", "*.toml")))
        self.assertGreaterEqual(len(files), 20)
        kinds = set()
        for f in files:
            sweep = pnb_sweep.load_sweep(f, check_files=False)
            kinds.add(sweep["kind"])
            self.assertGreaterEqual(pnb_sweep.job_count(sweep), 1, f)
            self.assertTrue(sweep["description"], "%s: no description" % f)
            if sweep["kind"] == "command":
                # Every command names the files it runs, so a changed driver or binary reruns it.
                self.assertTrue(sweep["depends"], "%s: no depends" % f)
        self.assertEqual(kinds, {"play", "command"})
        code, out = self.sweep("list")
        self.assertEqual(code, 0, out)
        listed = [line.split()[0] for line in out.splitlines()[:-1]]
        self.assertEqual(sorted(os.path.abspath(p) for p in listed), files)
        self.assertIn("%d experiment files" % len(files), out)
        # Every scripts/bench* runs one of them through pnb-sweep.
        for script in glob.glob(os.path.join(REPO, "scripts", "bench*")):
            with open(script) as f:
                text = f.read()
            self.assertIn("sweep/pnb_sweep.py experiment sweep/", text, script)
            named = text.rsplit("sweep/pnb_sweep.py experiment ", 1)[1].split()[0]
            self.assertIn(os.path.join(REPO, named), files, script)

    def test_a_command_experiment_runs_collects_and_reports(self):
        s = self.write("tiny.toml", WRITES_FIGURES)
        code, out = self.sweep("run", "--local", s, "--results", self.results)
        self.assertEqual(code, 0)
        self.assertIn("measured 2", out, "the command's output is echoed")
        keys = sorted(k for k in os.listdir(self.results) if not k.startswith("."))
        self.assertEqual(len(keys), 3)
        for k in keys:
            job = pnb_sweep.read_json(os.path.join(self.results, k, "job.json"))
            figures = pnb_sweep.read_json(os.path.join(self.results, k, "figures.json"))
            self.assertEqual(figures["twice"], 2 * int(job["settings"]["n"]))
            with open(os.path.join(self.results, k, "log.txt")) as f:
                self.assertIn("measured %s" % job["settings"]["n"], f.read())
        columns, rows = pnb_sweep.collect(self.results)
        self.assertEqual(sorted(r["fig:twice"] for r in rows), [2, 4, 6])
        self.assertEqual({r["kind"] for r in rows}, {"command"})
        # A rerun finds them finished; --rerun runs them again; extra arguments are new jobs.
        mtimes = {k: os.path.getmtime(os.path.join(self.results, k, "job.json")) for k in keys}
        code, out = self.sweep("run", "--local", s, "--results", self.results)
        self.assertEqual(out.count(": ran"), 0)
        code, out = self.sweep("run", "--local", "--rerun", s, "--results", self.results)
        self.assertEqual(out.count(": ran"), 3)
        self.assertTrue(all(os.path.getmtime(os.path.join(self.results, k, "job.json")) > mtimes[k] for k in keys))
        code, out = self.sweep("run", "--local", s, "--results", self.results, "--", "x", "y")
        self.assertEqual(out.count(": ran"), 3)
        _, rows = pnb_sweep.collect(self.results)
        self.assertEqual(sorted((r["args"], r["fig:nargs"]) for r in rows), [("", 0)] * 3 + [("x y", 2)] * 3)
        # The report: the figures' table and the index of every experiment file.
        report = os.path.join(self.dir, "report")
        code, out = self.sweep("report", self.results, "--sweep", s, "-o", report)
        self.assertEqual(code, 0, out)
        with open(os.path.join(report, "index.html")) as f:
            page = f.read()
        self.assertIn("tiny-command (command)", page)
        table = page.split("tiny-command (command)")[1].split("</table>")[0]
        self.assertIn("<td>twice</td>", table)
        self.assertEqual(table.count("<th>"), 4, "one column per job of this plan (3) beside the names")
        for v in ("2", "4", "6"):
            self.assertIn("<td align=right>%s</td>" % v, table)
        for f in glob.glob(os.path.join(REPO, "sweep", "experiments", "*.toml")):
            self.assertIn(os.path.relpath(f, REPO), page)

    def test_a_written_plans_command_job_runs_alone(self):
        # What a Slurm array task does (run --slurm writes the plan; each task runs run-job).
        s = self.write("tiny.toml", WRITES_FIGURES)
        plan_file = os.path.join(self.dir, "plan.json")
        code, out = self.sweep("plan", s, "--results", self.results, "-o", plan_file, "--", "z")
        self.assertEqual(code, 0)
        self.assertIn("3 jobs, 3 pending", out)
        code, out = self.sweep("run-job", plan_file, "1")
        self.assertEqual((code, out.strip()), (0, "job 1: ran"))
        code, out = self.sweep("run-job", plan_file, "1")
        self.assertEqual(out.strip(), "job 1: skipped")
        with open(plan_file) as f:
            job = json.load(f)["jobs"][1]
        figures = pnb_sweep.read_json(os.path.join(job["result"], "figures.json"))
        self.assertEqual((figures["n"], figures["nargs"]), (int(job["settings"]["n"]), 1))
        code, out = self.sweep("status", plan_file)
        self.assertIn("1 of 3 jobs finished", out)

    def test_figures_taken_from_the_commands_json_and_csv(self):
        s = self.write("files.toml", """
name = "from-files"
kind = "command"
command = ["{python}", "-c", "import json; json.dump({'runs': {'a': {'ms': 1.5}, 'b': {'ms': 2.5}}, 'ok': True, 'rows': [{'x': 7}]}, open('{out}/r.json', 'w')); open('{out}/t.csv', 'w').write('scene,config,total\\\\nbox,warm,12.5\\\\nbox,cold,30\\\\n')"]
[figures]
file = "r.json"
keys = ["runs.*.ms", "ok", "rows.0.x"]
""")
        self.assertEqual(self.sweep("run", "--local", s, "--results", self.results)[0], 0)
        _, rows = pnb_sweep.collect(self.results)
        self.assertEqual({k: v for k, v in rows[0].items() if k.startswith("fig:")},
                         {"fig:runs.a.ms": 1.5, "fig:runs.b.ms": 2.5, "fig:ok": True, "fig:rows.0.x": 7})
        with open(s) as f:
            text = f.read()
        csv_sweep = self.write("csv.toml", text.replace('name = "from-files"', 'name = "from-csv"').replace(
            'file = "r.json"\nkeys = ["runs.*.ms", "ok", "rows.0.x"]',
            'file = "t.csv"\nlabel = ["scene", "config"]\ncolumns = ["total"]'))
        self.assertEqual(self.sweep("run", "--local", csv_sweep, "--results", self.results)[0], 0)
        _, rows = pnb_sweep.collect(self.results)
        row = [r for r in rows if r["scene"] == "from-csv"][0]
        self.assertEqual(row["fig:box:warm:total"], 12.5)
        self.assertEqual(row["fig:box:cold:total"], 30.0)
        # A JSON list of records, named like CSV rows.
        records = self.write("records.toml", """
name = "from-records"
kind = "command"
command = ["{python}", "-c", "import json; json.dump({'results': [{'size': 'a', 'n': 1, 'd': {'ms': 3}}, {'size': 'b', 'n': 8, 'd': {'ms': 4}}]}, open('{out}/r.json', 'w'))"]
[figures]
file = "r.json"
rows = "results"
label = ["size", "n"]
columns = ["d.ms"]
""")
        self.assertEqual(self.sweep("run", "--local", records, "--results", self.results)[0], 0)
        _, rows = pnb_sweep.collect(self.results)
        row = [r for r in rows if r["scene"] == "from-records"][0]
        self.assertEqual({k: v for k, v in row.items() if k.startswith("fig:")},
                         {"fig:a:1:d.ms": 3, "fig:b:8:d.ms": 4})

    def test_a_failing_or_silent_command_leaves_no_finished_job(self):
        cases = {
            "fails.toml": ("[\"{python}\", \"-c\", \"import sys; print('broken'); sys.exit(3)\"]", "exit code 3"),
            "silent.toml": ("[\"{python}\", \"-c\", \"print('no figures')\"]", "wrote no figures.json"),
            "not-numbers.toml": ("[\"{python}\", \"-c\", \"open('{out}/figures.json', 'w').write('[1, 2]')\"]",
                                 "named numbers"),
        }
        for name, (command, words) in cases.items():
            s = self.write(name, 'kind = "command"\ncommand = %s\n' % command)
            data = pnb_sweep.plan(pnb_sweep.load_sweep(s), pnb_sweep.binaries(self.dir, "command"), self.results)
            with self.assertRaises(pnb_sweep.SweepError) as e:
                pnb_sweep.run_job(data, 0)
            self.assertIn(words, str(e.exception))
            self.assertIn("log.txt", str(e.exception), "the error names the job's log")
            self.assertFalse(pnb_sweep.done(data["jobs"][0]))
            self.assertFalse(os.path.exists(data["jobs"][0]["result"]))

    def test_the_job_key_follows_the_files_it_depends_on(self):
        driver = self.write("driver.py", "import json, sys\njson.dump({'v': 1}, open(sys.argv[1] + '/figures.json', 'w'))\n")
        s = self.write("dep.toml", 'kind = "command"\ncommand = ["{python}", "%s", "{out}"]\ndepends = ["%s"]\n'
                       % (driver, driver))
        bins = pnb_sweep.binaries(self.dir, "command")
        first = pnb_sweep.plan(pnb_sweep.load_sweep(s), bins, self.results)["jobs"][0]["key"]
        with open(driver, "a") as f:
            f.write("# changed\n")
        pnb_sweep.forget_hashes()
        self.assertNotEqual(pnb_sweep.plan(pnb_sweep.load_sweep(s), bins, self.results)["jobs"][0]["key"], first)
        os.remove(driver)
        pnb_sweep.forget_hashes()
        with self.assertRaises(pnb_sweep.SweepError) as e:
            pnb_sweep.plan(pnb_sweep.load_sweep(s), bins, self.results)
        self.assertIn("driver.py does not exist", str(e.exception))

    def test_bad_command_experiments_name_the_file_and_the_key(self):
        cases = {
            "a.toml": ('kind = "command"\n', "needs 'command'"),
            "b.toml": ('kind = "command"\ncommand = "echo"\n', "'command' must be a non-empty list"),
            "c.toml": ('kind = "command"\ncommand = ["{nope}"]\n', "unknown placeholder {nope}"),
            "d.toml": ('kind = "command"\ncommand = ["x"]\nscenes = []\n', "unknown key 'scenes'"),
            "e.toml": ('kind = "command"\ncommand = ["x"]\n[figures]\nfile = "t.csv"\n', "figures.label"),
            "f.toml": ('kind = "command"\ncommand = ["x"]\n[axes]\nout = ["a"]\n', "axes.out"),
            "g.toml": ('kind = "batch"\n', "kind: 'batch'"),
        }
        for name, (text, words) in cases.items():
            path = self.write(name, text)
            with self.assertRaises(pnb_sweep.SweepError) as e:
                pnb_sweep.load_sweep(path)
            self.assertIn(name, str(e.exception))
            self.assertIn(words, str(e.exception))
        code, out = self.sweep("list", os.path.join(self.dir, "c.toml"))
        self.assertEqual(code, 1)
        self.assertIn("unknown placeholder", out)

    def test_extra_arguments_are_only_for_command_experiments(self):
        scene = self.write("scene.glb", "not read")
        s = self.write("play.toml", '[[scenes]]\nsource = "%s"\n' % scene)
        with self.assertRaises(pnb_sweep.SweepError) as e:
            pnb_sweep.plan(pnb_sweep.load_sweep(s), {"play": scene, "convert": scene}, self.results, ["--x"])
        self.assertIn("command experiments", str(e.exception))

    def test_truth_metrics_are_judged_by_pnb_judge_and_the_rest_by_the_lean_player(self):
        bins = {"play": "/b/player/pnb-play", "judge": "/b/judge/pnb-judge"}
        self.assertEqual(pnb_sweep.player_for({"shadow": 8}, bins), bins["judge"])
        self.assertEqual(pnb_sweep.player_for({"gi": 4, "lod": 8}, bins), bins["judge"])
        self.assertEqual(pnb_sweep.player_for({"lod": 8}, bins), bins["play"])
        self.assertEqual(pnb_sweep.player_for({}, bins), bins["play"])
        with self.assertRaises(pnb_sweep.SweepError) as e:  # never the lean player, which refuses them
            pnb_sweep.player_for({"sky": 2}, dict(bins, judge=None))
        self.assertIn("needs pnb-judge", str(e.exception))


if __name__ == "__main__":
    unittest.main(verbosity=2)
