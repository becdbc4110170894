#!/usr/bin/env python3
"""pnb-sweep's planner and local runner on a tiny sweep: jobs, content-addressed results, reruns
that skip finished jobs, a changed axis that reruns only what changed, conversion caching, the
plan file a batch scheduler's task runs from, collection, and errors that name what is wrong.

Usage: sweep_local_test.py BUILD_DIR SCENE_DIR
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "sweep"))
import pnb_sweep  # noqa: E402

BUILD = SCENES = None


def sweep_toml(techniques, glb):
    return """
name = "tiny"
frames = 2
size = "64x36"
fixed = { "gi.enabled" = false }
[axes]
"shadows.technique" = [%s]
[[scenes]]
name = "box-room"
source = "%s"
[[scenes]]
name = "box-room-quantized"
source = "%s"
convert = ["--quantize"]
""" % (", ".join('"%s"' % t for t in techniques), os.path.join(SCENES, "box-room.pnb"), glb)


class SweepLocal(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="pnb_sweep_test_")
        self.results = os.path.join(self.dir, "results")
        self.glb = os.path.join(SCENES, "box-room.glb")

    def tearDown(self):
        subprocess.run(["rm", "-rf", self.dir])

    def write(self, name, text):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    @staticmethod
    def read(path):
        with open(path) as f:
            return f.read()

    def sweep(self, *args):
        return pnb_sweep.main(["--build", BUILD] + list(args))

    def test_runs_skips_and_reruns_only_what_changed(self):
        s = self.write("tiny.toml", sweep_toml(["off", "single"], self.glb))
        self.assertEqual(self.sweep("run", "--local", s, "--results", self.results), 0)
        done = sorted(k for k in os.listdir(self.results) if k != "converted")
        self.assertEqual(len(done), 4, "2 scenes x 2 techniques")
        for key in done:
            job = pnb_sweep.read_json(os.path.join(self.results, key, "job.json"))
            summary = pnb_sweep.read_json(os.path.join(self.results, key, "summary.json"))
            self.assertEqual(summary["settings"]["shadows.technique"], job["settings"]["shadows.technique"])
            self.assertEqual(job["settings"]["gi.enabled"], "false")
        converted = os.listdir(os.path.join(self.results, "converted"))
        self.assertEqual(len([f for f in converted if f.endswith(".pnb")]), 1, "one conversion, cached")
        mtimes = {k: os.path.getmtime(os.path.join(self.results, k, "job.json")) for k in done}
        # A rerun finds every job finished.
        sweep = pnb_sweep.load_sweep(s)
        data = pnb_sweep.plan(sweep, pnb_sweep.binaries(BUILD), self.results)
        self.assertEqual([j for j in data["jobs"] if not pnb_sweep.done(j)], [])
        self.assertEqual(self.sweep("run", "--local", s, "--results", self.results), 0)
        for k in done:
            self.assertEqual(os.path.getmtime(os.path.join(self.results, k, "job.json")), mtimes[k])
        # One more axis value: only its two jobs are new; the others keep their keys.
        s2 = self.write("tiny2.toml", sweep_toml(["off", "single", "pssm"], self.glb))
        data2 = pnb_sweep.plan(pnb_sweep.load_sweep(s2), pnb_sweep.binaries(BUILD), self.results)
        pending = [j for j in data2["jobs"] if not pnb_sweep.done(j)]
        self.assertEqual(sorted(j["settings"]["shadows.technique"] for j in pending), ["pssm", "pssm"])
        # The plan file is what a scheduler's array task runs one job of.
        plan_file = os.path.join(self.dir, "plan.json")
        self.assertEqual(self.sweep("plan", s2, "--results", self.results, "-o", plan_file), 0)
        for j in pending:
            self.assertEqual(self.sweep("run-job", plan_file, str(j["index"])), 0)
        self.assertTrue(all(pnb_sweep.done(j) for j in data2["jobs"]))
        # Collected: one row per job, with the renderer and the GPU time per pass.
        out = os.path.join(self.dir, "results.csv")
        self.assertEqual(self.sweep("collect", self.results, "-o", out), 0)
        with open(out) as f:
            rows = f.read().strip().splitlines()
        self.assertEqual(len(rows), 1 + 6)
        self.assertIn("gl_renderer", rows[0])
        self.assertIn("gpu_ms:total", rows[0])
        # --sweep: only the jobs one sweep file plans (the directory holds both sweeps' jobs).
        self.assertEqual(self.sweep("collect", self.results, "--sweep", s, "-o", out), 0)
        with open(out) as f:
            self.assertEqual(len(f.read().strip().splitlines()), 1 + 4)
        # The report: a page that references only files written beside it.
        report = os.path.join(self.dir, "report")
        self.assertEqual(self.sweep("report", self.results, "-o", report), 0)
        with open(os.path.join(report, "index.html")) as f:
            page = f.read()
        self.assertNotIn("http", page)
        for scene in ("box-room", "box-room-quantized"):
            self.assertIn("<h2>%s</h2>" % scene, page)
            self.assertTrue(os.path.getsize(os.path.join(report, scene + "_passes.png")) > 1000)
            self.assertTrue(os.path.getsize(os.path.join(report, scene + "_path.png")) > 1000)
        frames = os.listdir(os.path.join(report, "frames"))
        self.assertEqual(len(frames), 6, "one image per configuration in the gallery")
        for f in frames:
            self.assertIn('src="frames/%s"' % f, page)

    def test_batch_conversion_skips_outputs_whose_inputs_did_not_change(self):
        import shutil
        inputs = os.path.join(self.dir, "in")
        os.makedirs(inputs)
        for name in ("box-room", "grazing-plane"):
            shutil.copy(os.path.join(SCENES, name + ".glb"), os.path.join(inputs, name + ".glb"))
        out = os.path.join(self.dir, "converted")
        self.assertEqual(self.sweep("convert", "--local", inputs, "-o", out), 0)
        pnbs = sorted(f for f in os.listdir(out) if f.endswith(".pnb"))
        self.assertEqual(pnbs, ["box-room.pnb", "grazing-plane.pnb"])
        mtimes = {f: os.path.getmtime(os.path.join(out, f)) for f in pnbs}
        # Unchanged inputs: nothing converted again.
        self.assertEqual(self.sweep("convert", "--local", inputs, "-o", out), 0)
        for f in pnbs:
            self.assertEqual(os.path.getmtime(os.path.join(out, f)), mtimes[f], f)
        # One input changed: only its output is made again; the other is kept.
        shutil.copy(os.path.join(SCENES, "box-room.glb"), os.path.join(inputs, "grazing-plane.glb"))
        pnb_sweep.forget_hashes()  # as a new process would
        self.assertEqual(self.sweep("convert", "--local", inputs, "-o", out), 0)
        self.assertEqual(os.path.getmtime(os.path.join(out, "box-room.pnb")), mtimes["box-room.pnb"])
        self.assertNotEqual(os.path.getmtime(os.path.join(out, "grazing-plane.pnb")), mtimes["grazing-plane.pnb"])
        # The outputs are what pnb-convert writes for the same input, byte for byte.
        direct = os.path.join(self.dir, "direct.pnb")
        subprocess.run([os.path.join(BUILD, "converter", "pnb-convert"), os.path.join(inputs, "box-room.glb"),
                        "-o", direct, "-q"], check=True)
        with open(direct, "rb") as a, open(os.path.join(out, "box-room.pnb"), "rb") as b:
            self.assertEqual(a.read(), b.read())
        # Other options: everything again. A missing input: an error naming it.
        self.assertEqual(self.sweep("convert", "--local", inputs, "-o", out, "--", "--quantize"), 0)
        self.assertNotEqual(os.path.getmtime(os.path.join(out, "box-room.pnb")), mtimes["box-room.pnb"])
        listing = self.write("list.txt", "in/box-room.glb\nin/nothing.glb\n")
        self.assertEqual(self.sweep("convert", "--local", listing, "-o", out), 1)

    def test_converter_axes_and_axis_groups(self):
        s = self.write("conv.toml", """
name = "conv"
frames = 2
size = "64x36"
metrics = { shadow = 1 }
[[axes]]
"shadows.technique" = ["off", "single"]
[[axes]]
"shadows.technique" = ["off"]
"convert.quantize" = [true, false]
[[axes]]
"shadows.technique" = ["off"]          # the first group's again: planned once
[[scenes]]
name = "box-room"
source = "%s"
""" % self.glb)
        data = pnb_sweep.plan(pnb_sweep.load_sweep(s), pnb_sweep.binaries(BUILD), self.results)
        self.assertEqual(len(data["jobs"]), 4, "2 + 2 combinations, the repeated one once")
        by_quantize = {j["settings"].get("convert.quantize"): j for j in data["jobs"]
                       if j["settings"]["shadows.technique"] == "off"}
        self.assertEqual(by_quantize["true"]["convert"], ["--quantize"])
        self.assertEqual(by_quantize["false"]["convert"], [])
        # "false" is the option left out: the same conversion as no option at all.
        self.assertEqual(by_quantize["false"]["conversion"], by_quantize[None]["conversion"])
        self.assertNotEqual(by_quantize["true"]["conversion"], by_quantize[None]["conversion"])
        # Conversions two at a time, then the jobs one at a time (the default: they share the GPU).
        self.assertEqual(self.sweep("run", "--local", s, "--results", self.results, "-j", "2"), 0)
        spans = sorted((j["started"], j["finished"]) for j in
                       (pnb_sweep.read_json(os.path.join(d["result"], "job.json")) for d in data["jobs"]))
        for (_, end), (start, _) in zip(spans, spans[1:]):
            self.assertLessEqual(end, start, "GPU jobs never overlap with --gpu-jobs 1")
        converted = os.listdir(os.path.join(self.results, "converted"))
        self.assertEqual(sorted(f for f in converted if f.endswith(".pnb")),
                         sorted({j["conversion"] + ".pnb" for j in data["jobs"]}))
        self.assertFalse([f for f in converted if ".tmp." in f], "no conversion left half-made")
        for j in data["jobs"]:
            log = self.read(os.path.join(j["result"], "log.txt")).splitlines()[0]
            self.assertNotIn("convert.quantize", log, "converter options are not player settings")
        columns, rows = pnb_sweep.collect(self.results)
        quantized = [r for r in rows if r.get("set:convert.quantize") == "true"]
        plain = [r for r in rows if r.get("set:convert.quantize") != "true"]
        self.assertEqual((len(quantized), len(plain)), (1, 3))
        self.assertGreater(quantized[0]["convert:max_position_error"], 0)
        self.assertLess(quantized[0]["convert:output_bytes"], plain[0]["convert:output_bytes"])
        for r in rows:
            self.assertEqual(r["load:file_bytes"], r["convert:output_bytes"], "the container played")
            self.assertGreater(r["load_ms:total"], 0)
            for phase in pnb_sweep.LOAD_PHASES:
                self.assertIn("load_ms:" + phase, r)
            if pnb_sweep.binaries(BUILD)["probe"]:
                self.assertGreater(float(r["load_ms:floor"]), 0)
                self.assertLess(float(r["load_ms:floor"]), float(r["load_ms:total"]), "a floor below the load")
        for r in plain:
            self.assertEqual(r["convert:max_position_error"], 0, "not quantised: exact")
        report = os.path.join(self.dir, "report")
        self.assertEqual(self.sweep("report", self.results, "-o", report), 0)
        page = self.read(os.path.join(report, "index.html"))
        self.assertIn("mesh quantisation: max position error", page)
        self.assertIn("--quantize", page)
        self.assertIn("<h3>Load time</h3>", page)
        # The gallery: each job's last measured frame beside that frame's shadow error map, with
        # the map's legend.
        for j in data["jobs"]:
            for image in ("frame.png", "error_shadow.png"):
                self.assertIn('src="frames/%s_%s"' % (j["key"], image), page)
                self.assertTrue(os.path.exists(os.path.join(report, "frames", "%s_%s" % (j["key"], image))))
        self.assertIn("false lit", page)
        self.assertTrue(os.path.getsize(os.path.join(report, "box-room_max_position_error.png")) > 1000)
        self.assertTrue(os.path.getsize(os.path.join(report, "box-room_load.png")) > 1000)
        missing = os.path.join(self.dir, "none.csv")
        r = subprocess.run([sys.executable, os.path.join(REPO, "sweep", "pnb_sweep.py"), "--build", BUILD,
                            "report", self.results, "-o", report, "--extremes", missing],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn(missing + ": no extremes matrix", r.stderr)
        # Converter axes on a container: nothing to convert, an error naming the scene.
        bad = self.write("bad.toml", '[axes]\n"convert.quantize" = [true]\n[[scenes]]\nsource = "%s"\n'
                         % os.path.join(SCENES, "box-room.pnb"))
        with self.assertRaises(pnb_sweep.SweepError) as e:
            pnb_sweep.load_sweep(bad)
        self.assertIn("box-room.pnb", str(e.exception))

    def test_the_report_shows_the_extremes_matrix_with_its_bands(self):
        matrix = self.write("matrix.csv", "row,scale,technique,misclassified_pct,weighted_error_pct,in_band\n"
                            "street,1,sdsm,0.022,0.175,yes\nstreet,1e5,sdsm,0.031,0.180,yes\n"
                            "wide-flat,1e3,sdsm,4.5,6.1,no\n")
        columns = ["key", "scene", "set:shadows.technique", "gpu_ms:total", "metric:misclassified_pct"]
        rows = [{"key": "a", "scene": "s", "set:shadows.technique": "pssm", "gpu_ms:total": 2.0,
                 "metric:misclassified_pct": 0.5}]
        import sweep_report
        page = self.read(sweep_report.write_report(columns, rows, os.path.join(self.dir, "r"), None, matrix))
        self.assertIn("<h2>Numerical extremes</h2>", page)
        self.assertIn("<td>0.022 / 0.175</td>", page)
        self.assertIn("color:#c00000;font-weight:bold\">4.500 / 6.100", page, "out of band: marked")
        self.assertIn("<th>x1e5</th>", page)

    def test_several_gpus_get_a_front_each(self):
        import sweep_report
        columns = ["key", "scene", "set:shadows.technique", "gl_renderer", "gpu_ms:total", "metric:misclassified_pct"]
        rows = []
        for renderer, speed in (("GPU A", 1.0), ("GPU B", 10.0)):
            for t, ms, err in (("single", 1.0, 5.0), ("pssm", 2.0, 1.0), ("sdsm", 3.0, 2.0)):
                rows.append({"key": renderer + t, "scene": "s", "set:shadows.technique": t, "gl_renderer": renderer,
                             "gpu_ms:total": ms * speed, "metric:misclassified_pct": err})
        page = self.read(sweep_report.write_report(columns, rows, os.path.join(self.dir, "r")))
        # On B every configuration is 10x slower: A's fast ones would hide B's whole front if mixed.
        for renderer in ("GPU A", "GPU B"):
            self.assertIn("<td>%s</td><td>technique=single</td>" % renderer, page)
            self.assertIn("<td>%s</td><td>technique=pssm</td>" % renderer, page)
            self.assertNotIn("<td>%s</td><td>technique=sdsm</td>" % renderer, page)

    def test_the_gi_cost_table_shares_the_frame_and_compares_with_gi_off(self):
        import sweep_report
        columns = ["key", "scene", "size", "set:gi.enabled", "set:gi.technique", "gpu_ms:total",
                   "gpu_ms:gi_rsm", "gpu_ms:gi_propagate", "gpu_ms:lighting"]
        rows = [{"key": "off", "scene": "s", "size": "1280x720", "set:gi.enabled": False, "gpu_ms:total": 100.0},
                {"key": "lpv", "scene": "s", "size": "1280x720", "set:gi.enabled": True, "set:gi.technique": "lpv",
                 "gpu_ms:total": 150.0, "gpu_ms:gi_rsm": 10.0, "gpu_ms:gi_propagate": 20.0, "gpu_ms:lighting": 60.0},
                {"key": "probes", "scene": "s", "size": "1280x720", "set:gi.enabled": "true",
                 "set:gi.technique": "probes", "gpu_ms:total": 110.0, "gpu_ms:gi_rsm": 0.0}]
        page = self.read(sweep_report.write_report(columns, rows, os.path.join(self.dir, "r")))
        self.assertIn("<h3>GI cost, share of the frame (1280x720)</h3>", page)
        # LPV: 30 of its 150 ms in GI's passes (20 %), +50 % on the 100 ms GI-off frame.
        self.assertIn("<td>150.0</td><td>30.0</td><td>20 %</td><td>+50 %</td>", page)
        self.assertIn("<td>110.0</td><td>0.0</td><td>0 %</td><td>+10 %</td>", page)
        self.assertIn("GI off: 100.0 ms per frame", page)

    def test_scenes_named_by_light_count_get_a_chart_and_ratios(self):
        import sweep_report
        columns = ["key", "scene", "set:lights.culling", "gpu_ms:total"]
        rows = []
        for culling, per_light in (("off", 1.0), ("clusters", 0.01)):
            for n in (8, 64, 1024):
                rows.append({"key": culling + str(n), "scene": "field-%d" % n, "set:lights.culling": culling,
                             "gpu_ms:total": 100.0 + per_light * n})
        rows.append({"key": "x", "scene": "box-room", "set:lights.culling": "off", "gpu_ms:total": 5.0})
        out = os.path.join(self.dir, "r")
        page = self.read(sweep_report.write_report(columns, rows, out))
        self.assertIn("<h2>Frame time by light count: field</h2>", page)
        self.assertTrue(os.path.exists(os.path.join(out, "field_light_count.png")))
        self.assertNotIn("light count: box-room", page)  # one scene of its name: no family
        # off: 1124 ms at 1024 lights over 108 ms at 8; clusters: 110.24 over 100.08.
        self.assertIn("<td>1124.0 ms (10.41x)</td>", page)
        self.assertIn("<td>110.2 ms (1.10x)</td>", page)

    def test_the_pareto_front_keeps_what_nothing_beats(self):
        import sweep_report
        points = [(1.0, 5.0), (2.0, 3.0), (3.0, 4.0), (4.0, 1.0), (2.5, 3.0), (0.5, 9.0)]
        self.assertEqual(sorted(sweep_report.pareto_front(points)), [0, 1, 3, 5])

    def test_an_interrupted_job_is_not_finished(self):
        s = self.write("tiny.toml", sweep_toml(["off"], self.glb))
        data = pnb_sweep.plan(pnb_sweep.load_sweep(s), pnb_sweep.binaries(BUILD), self.results)
        job = data["jobs"][0]
        os.makedirs(job["result"])  # what a killed task leaves: a directory without job.json
        with open(os.path.join(job["result"], "summary.json"), "w") as f:
            f.write("{")
        self.assertFalse(pnb_sweep.done(job))
        self.assertEqual(pnb_sweep.run_job(data, 0), "ran")
        self.assertTrue(pnb_sweep.done(job))

    def test_bad_sweeps_name_the_file_and_the_key(self):
        cases = {
            "a.toml": ("frames = [", "not valid TOML"),
            "b.toml": ('name = "x"\n', "'scenes'"),
            "c.toml": ('[[scenes]]\nsource = "missing.glb"\n', "missing.glb"),
            "d.toml": ('colour = 1\n[[scenes]]\nsource = "%s"\n' % self.glb, "unknown key 'colour'"),
            "e.json": ('{"scenes": [{"source": "%s"}], "metrics": {"shadows": 4}}' % self.glb, "metrics.shadows"),
        }
        for name, (text, words) in cases.items():
            path = self.write(name, text)
            with self.assertRaises(pnb_sweep.SweepError) as e:
                pnb_sweep.load_sweep(path)
            self.assertIn(name, str(e.exception))
            self.assertIn(words, str(e.exception))
        r = subprocess.run([sys.executable, os.path.join(REPO, "sweep", "pnb_sweep.py"), "--build", BUILD,
                            "plan", os.path.join(self.dir, "a.toml")], capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn("a.toml", r.stderr)


if __name__ == "__main__":
    BUILD, SCENES = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    unittest.main(argv=sys.argv[:1], verbosity=2)
