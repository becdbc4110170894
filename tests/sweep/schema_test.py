#!/usr/bin/env python3
"""pnb-sweep's experiment files against their schemas (issue 41, item 6; sweep/sweep_schema.py):
malformed sweep files and command experiments — a wrong type per key, nan and inf, a table where
a string belongs and the reverse, unknown keys at the top and inside, empty lists, values outside
a fixed set, negative frames, a malformed size — each end in exit 1 with one message naming the
file and the key (and what was expected), never a traceback; every file of sweep/examples and
sweep/experiments is valid. The job limit: 10^8 jobs from 8 axes are counted and refused at once
with how the count arises; --max-jobs above the count and --yes let planning proceed.

usage: schema_test.py BUILD_DIR SCENE_DIR
"""
import glob
import os
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
import unittest

BUILD, SCENES = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "sweep"))
import pnb_sweep  # noqa: E402
import sweep_schema  # noqa: E402

SWEEP = os.path.join(REPO, "sweep", "pnb_sweep.py")
SCENE = os.path.join(SCENES, "box-room.pnb")
ONE_SCENE = '[[scenes]]\nsource = "%s"\n' % SCENE
COMMAND = 'kind = "command"\ncommand = ["{python}", "-c", "pass"]\n'

# name: (file text, what the message must say besides the file's name). The first word is the
# key as the message writes it; each file has one fault, so every jsonschema picks the same one.
PLAY_CASES = {
    "frames-string.toml": ('frames = "x"\n' + ONE_SCENE, ["'frames'", "a whole number", "'x'"]),
    "frames-nan.toml": ("frames = nan\n" + ONE_SCENE, ["'frames'", "got nan"]),
    "frames-inf.toml": ("frames = inf\n" + ONE_SCENE, ["'frames'", "got inf"]),
    "frames-negative.toml": ("frames = -5\n" + ONE_SCENE, ["'frames'", ">= 1", "got -5"]),
    "frames-fraction.toml": ("frames = 2.5\n" + ONE_SCENE, ["'frames'", "a whole number"]),
    "size-number.toml": ("size = 320\n" + ONE_SCENE, ["'size'", "WIDTHxHEIGHT"]),
    "size-64x.toml": ('size = "64x"\n' + ONE_SCENE, ["'size'", "WIDTHxHEIGHT", "'64x'"]),
    "name-table.toml": (ONE_SCENE + "[name]\nx = 1\n", ["'name'", "got a table"]),
    "name-slash.toml": ('name = "a/b"\n' + ONE_SCENE, ["'name'", "letters, digits"]),
    "description-list.toml": ('description = ["a"]\n' + ONE_SCENE, ["'description'", "a string"]),
    "kind-unknown.toml": ('kind = "batch"\n' + ONE_SCENE, ["kind: 'batch'", "(play, command)"]),
    "kind-number.toml": ("kind = 3\n" + ONE_SCENE, ["kind: 3", "(play, command)"]),
    "unknown-top-level.toml": ("colour = 1\n" + ONE_SCENE, ["unknown key 'colour'", "known: axes, description"]),
    "metrics-unknown.toml": ("metrics = { shadows = 4 }\n" + ONE_SCENE,
                             ["unknown key 'metrics.shadows'", "known: frame, gi, lod, shadow, sky"]),
    "metrics-zero.toml": ("metrics = { shadow = 0 }\n" + ONE_SCENE, ["'metrics.shadow'", ">= 1"]),
    "metrics-nan.toml": ("metrics = { gi = nan }\n" + ONE_SCENE, ["'metrics.gi'", "got nan"]),
    "metrics-string.toml": ('metrics = "shadow"\n' + ONE_SCENE, ["'metrics'", "a table"]),
    "fixed-string.toml": ('fixed = "gi.enabled=false"\n' + ONE_SCENE, ["'fixed'", "a table"]),
    "fixed-value-table.toml": ('fixed = { "gi.enabled" = { on = true } }\n' + ONE_SCENE,
                               ["'fixed.\"gi.enabled\"'", "got a table"]),
    "fixed-unquoted-key.toml": ("fixed = { gi.enabled = false }\n" + ONE_SCENE, ["key 'fixed.gi'", "quoted in TOML"]),
    "fixed-nan.toml": ('fixed = { "lighting.exposure" = nan }\n' + ONE_SCENE,
                       ["'fixed.\"lighting.exposure\"'", "a finite number", "got nan"]),
    "axes-string.toml": ('axes = "shadows.technique"\n' + ONE_SCENE, ["'axes'", "[[axes]]"]),
    "axes-value-string.toml": ('[axes]\n"shadows.technique" = "pssm"\n' + ONE_SCENE,
                               ["'axes.\"shadows.technique\"'", "a non-empty list", "'pssm'"]),
    "axes-values-empty.toml": ('[axes]\n"shadows.technique" = []\n' + ONE_SCENE,
                               ["'axes.\"shadows.technique\"'", "got an empty list"]),
    "axes-empty-list.toml": ("axes = []\n" + ONE_SCENE, ["'axes'", "got an empty list"]),
    "axes-group-string.toml": ('axes = ["shadows.technique"]\n' + ONE_SCENE, ["'axes[0]'", "a table of setting keys"]),
    "axes-inf.toml": ('[[axes]]\n"shadows.cascades" = [2, inf]\n' + ONE_SCENE,
                      ["'axes[0].\"shadows.cascades\"[1]'", "a finite number", "got inf"]),
    "axes-nested-list.toml": ('[axes]\n"shadows.cascades" = [[2, 4]]\n' + ONE_SCENE,
                              ["'axes.\"shadows.cascades\"[0]'", "got a list"]),
    "axes-unquoted-key.toml": ('[axes]\nshadows.technique = ["pssm"]\n' + ONE_SCENE,
                               ["key 'axes.shadows'", "\"section.name\""]),
    "scenes-missing.toml": ('name = "x"\n', ["needs 'scenes'", "[[scenes]]"]),
    "scenes-empty.toml": ("scenes = []\n", ["'scenes'", "got an empty list"]),
    "scenes-table.toml": ('[scenes]\nsource = "%s"\n' % SCENE, ["'scenes'", "a non-empty list of tables", "got a table"]),
    "scene-source-table.toml": ("[[scenes]]\n[scenes.source]\nfile = \"x.glb\"\n",
                                ["'scenes[0].source'", "a non-empty string", "got a table"]),
    "scene-second-source-number.toml": (ONE_SCENE + "[[scenes]]\nsource = 3\n", ["'scenes[1].source'", "got 3"]),
    "scene-no-source.toml": ('[[scenes]]\nname = "x"\n', ["needs 'scenes[0].source'"]),
    "scene-unknown-key.toml": (ONE_SCENE + "colour = 1\n", ["unknown key 'scenes[0].colour'", "known: convert, name"]),
    "scene-convert-string.toml": (ONE_SCENE + 'convert = "--sky"\n', ["'scenes[0].convert'", "a list of strings"]),
    "scene-convert-number.toml": (ONE_SCENE + 'convert = ["--sky", 2]\n', ["'scenes[0].convert[1]'", "a string"]),
    "scene-path-empty.toml": (ONE_SCENE + 'path = ""\n', ["'scenes[0].path'", "a non-empty string"]),
    "top-level-list.json": ("[1, 2]", ["the top level must be a table"]),
    "frames-nan.json": ('{"frames": NaN, "scenes": [{"source": "%s"}]}' % SCENE, ["'frames'", "got nan"]),
    "axes-infinity.json": ('{"axes": {"shadows.cascades": [-Infinity]}, "scenes": [{"source": "%s"}]}' % SCENE,
                           ["'axes.\"shadows.cascades\"[0]'", "got -inf"]),
}
COMMAND_CASES = {
    "command-missing.toml": ('kind = "command"\n', ["needs 'command'", "a non-empty list of strings"]),
    "command-string.toml": ('kind = "command"\ncommand = "echo"\n', ["'command' must be a non-empty list"]),
    "command-empty.toml": ('kind = "command"\ncommand = []\n', ["'command'", "got an empty list"]),
    "command-number.toml": ('kind = "command"\ncommand = ["echo", 3]\n', ["'command[1]'", "a string", "got 3"]),
    "command-table.toml": ('kind = "command"\n[command]\nprogram = "echo"\n', ["'command'", "got a table"]),
    "depends-string.toml": (COMMAND + 'depends = "x.py"\n', ["'depends'", "a non-empty list of strings"]),
    "depends-empty.toml": (COMMAND + "depends = []\n", ["'depends'", "got an empty list"]),
    "depends-table.toml": (COMMAND + '[depends]\nfile = "x.py"\n', ["'depends'", "got a table"]),
    "args-string.toml": (COMMAND + 'args = "--quick"\n', ["'args'", "a list of strings"]),
    "env-number.toml": (COMMAND + "env = { EGL_LOG_LEVEL = 1 }\n", ["'env.EGL_LOG_LEVEL'", "a string"]),
    "env-bad-name.toml": (COMMAND + 'env = { "A B" = "x" }\n', ["key 'env.\"A B\"'", "environment variable"]),
    "figures-string.toml": (COMMAND + 'figures = "out.csv"\n', ["'figures'", "a table with 'file'"]),
    "figures-no-file.toml": (COMMAND + '[figures]\nkeys = ["a"]\n', ["needs 'figures.file'"]),
    "figures-csv-no-label.toml": (COMMAND + '[figures]\nfile = "t.csv"\ncolumns = ["a"]\n',
                                  ["needs 'figures.label'", "a non-empty list of strings"]),
    "figures-json-no-keys.toml": (COMMAND + '[figures]\nfile = "t.json"\n', ["needs 'figures.keys'"]),
    "figures-unknown-key.toml": (COMMAND + '[figures]\nfile = "t.json"\nkeys = ["a"]\ncolumn = ["b"]\n',
                                 ["unknown key 'figures.column'", "known: columns, file, keys, label, rows"]),
    "figures-keys-string.toml": (COMMAND + '[figures]\nfile = "t.json"\nkeys = "a"\n', ["'figures.keys'", "got 'a'"]),
    "figures-rows-list.toml": (COMMAND + '[figures]\nfile = "t.json"\nrows = ["r"]\nlabel = ["a"]\ncolumns = ["b"]\n',
                               ["'figures.rows'", "a non-empty string"]),
    "command-axes-builtin.toml": (COMMAND + '[axes]\nout = ["a"]\n', ["key 'axes.out'", "not repo, build, out, python"]),
    "command-axes-bad-name.toml": (COMMAND + '[axes]\n"a-b" = ["a"]\n', ["key 'axes.a-b'", "a placeholder name"]),
    "command-axes-nan.toml": (COMMAND + "[axes]\nn = [1, nan]\n", ["'axes.n[1]'", "got nan"]),
    "command-unknown-key.toml": (COMMAND + "scenes = []\n", ["unknown key 'scenes'", "known: args, axes, command"]),
}


def axes_text(sizes, quote=True):
    """An axes table of len(sizes) axes, the i-th with sizes[i] values."""
    return "".join('"%s" = [%s]\n' % ("a.k%d" % i if quote else "k%d" % i, ", ".join(str(v) for v in range(n)))
                   for i, n in enumerate(sizes))


class Schema(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="pnb_sweep_schema_")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def write(self, name, text):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def sweep(self, *args):
        return subprocess.run([sys.executable, SWEEP, "--build", BUILD] + list(args), capture_output=True, text=True)

    def test_malformed_files_name_the_file_and_the_key(self):
        cases = dict(PLAY_CASES, **COMMAND_CASES)
        self.assertGreaterEqual(len(cases), 32)
        for name, (text, words) in cases.items():
            with self.subTest(name):
                path = self.write(name, text)
                with self.assertRaises(pnb_sweep.SweepError) as e:
                    pnb_sweep.load_sweep(path)
                for w in [path] + words:
                    self.assertIn(w, str(e.exception))
                r = self.sweep("plan", path)
                self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
                self.assertNotIn("Traceback", r.stderr)
                self.assertEqual(r.stderr.strip().splitlines(), ["pnb-sweep: " + str(e.exception)], "one line")

    def test_files_the_parsers_refuse_are_errors_too(self):
        for name, data, words in (("not-utf8.toml", b'name = "\xff"\n', "not valid TOML"),
                                  ("deep.json", b'{"axes": ' + b"[" * 100000 + b"]" * 100000 + b"}", "not valid JSON")):
            with self.subTest(name):
                path = os.path.join(self.dir, name)
                with open(path, "wb") as f:
                    f.write(data)
                r = self.sweep("plan", path)
                self.assertEqual(r.returncode, 1)
                self.assertNotIn("Traceback", r.stderr)
                self.assertIn("%s: %s" % (path, words), r.stderr)

    def test_every_experiment_file_of_the_repository_is_valid(self):
        files = sorted(glob.glob(os.path.join(REPO, "sweep", "examples", "*.toml")) +
                       glob.glob(os.path.join(REPO, "sweep", "experiments", "*.toml")))
        self.assertGreaterEqual(len(files), 20)
        for f in files:
            with open(f, "rb") as fh:
                sweep_schema.validate(f, tomllib.load(fh))
        r = self.sweep("list")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("%d experiment files\n" % len(files), r.stdout)

    def test_the_schemas_are_json_schemas_and_know_every_metric(self):
        for schema in (sweep_schema.TOP, sweep_schema.PLAY, sweep_schema.COMMAND):
            sweep_schema.Validator.check_schema(schema)
        self.assertEqual(set(sweep_schema.METRICS), set(pnb_sweep.METRIC_FLAGS))

    def test_too_many_jobs_are_counted_and_refused_at_once(self):
        big = self.write("big.toml", "[axes]\n" + axes_text([10] * 8) + ONE_SCENE)
        started = time.monotonic()
        with self.assertRaises(pnb_sweep.SweepError) as e:
            pnb_sweep.plan(pnb_sweep.load_sweep(big), pnb_sweep.binaries(BUILD), os.path.join(self.dir, "r"))
        self.assertLess(time.monotonic() - started, 0.5, "counted, not expanded")
        self.assertIn("%s: 100000000 jobs (1 scene x %s), more than the limit of %d"
                      % (big, " x ".join(["10"] * 8), pnb_sweep.JOB_LIMIT), str(e.exception))
        r = self.sweep("plan", big)
        self.assertEqual(r.returncode, 1)
        self.assertIn("100000000 jobs", r.stderr)
        self.assertIn("--max-jobs 100000000 or --yes", r.stderr)
        r = self.sweep("list", big)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("100000000", r.stdout)
        # A command experiment's jobs too, and run and experiment refuse like plan.
        command = self.write("big-command.toml", COMMAND + "[axes]\n" + axes_text([10] * 8, quote=False))
        for sub in (["plan"], ["run", "--local"], ["experiment"]):
            r = self.sweep(*sub, command)
            self.assertEqual(r.returncode, 1, sub)
            self.assertIn("100000000 jobs (%s)" % " x ".join(["10"] * 8), r.stderr)

    def test_the_limit_is_raised_by_max_jobs_or_yes(self):
        six = self.write("six.toml", "[axes]\n" + axes_text([2, 3]) + ONE_SCENE)
        r = self.sweep("plan", "--max-jobs", "5", six, "--results", os.path.join(self.dir, "r"))
        self.assertEqual(r.returncode, 1)
        self.assertIn("6 jobs (1 scene x 2 x 3), more than the limit of 5; to plan them, give --max-jobs 6 or --yes",
                      r.stderr)
        for option in (["--max-jobs", "6"], ["--yes"]):
            r = self.sweep("plan", *option, six, "--results", os.path.join(self.dir, "r"))
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("6 jobs, 6 pending", r.stdout)
        # The default limit: JOB_LIMIT jobs plan, one more does not.
        limit = pnb_sweep.JOB_LIMIT
        at = self.write("at.toml", "[axes]\n" + axes_text([limit]) + ONE_SCENE)
        over = self.write("over.toml", "[axes]\n" + axes_text([limit + 1]) + ONE_SCENE)
        bins = pnb_sweep.binaries(BUILD)
        self.assertEqual(len(pnb_sweep.plan(pnb_sweep.load_sweep(at), bins, self.dir)["jobs"]), limit)
        with self.assertRaises(pnb_sweep.SweepError) as e:
            pnb_sweep.plan(pnb_sweep.load_sweep(over), bins, self.dir)
        self.assertIn("%d jobs" % (limit + 1), str(e.exception))

    def test_axis_groups_are_counted_as_the_planner_combines_them(self):
        # Two groups over the same keys (under the fixed setting) share 2 combinations; a value
        # given twice is one job.
        s = self.write("groups.toml", 'fixed = { "gi.enabled" = false }\n'
                       '[[axes]]\n"shadows.technique" = ["pssm", "sdsm"]\n"shadows.cascades" = [2, 4, 4]\n'
                       '[[axes]]\n"shadows.technique" = ["sdsm", "single"]\n"shadows.cascades" = [2, 4]\n'
                       '[[axes]]\n"gi.enabled" = [true]\n' + ONE_SCENE + ONE_SCENE)
        sweep = pnb_sweep.load_sweep(s)
        self.assertEqual(pnb_sweep.job_count(sweep), 2 * len(pnb_sweep.play_combinations(sweep)))
        self.assertEqual(pnb_sweep.job_count(sweep), 2 * (4 + 4 - 2 + 1))
        self.assertEqual(pnb_sweep.job_count_terms(sweep), "2 scenes x (2 x 2 + 2 x 2 + 1) less 2 shared")


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
