#!/usr/bin/env python3
"""pnb-sweep's outputs never replace its inputs (issue 41, item 1): `plan -o` onto the sweep
file, `collect -o` onto a sweep file, `convert` with two inputs of one stem (one output file,
which would be reported as two) or through a symlinked output directory are refused with a
message naming both files; the inputs stay byte-identical. Also the rule itself
(sweep/output_guard.py): hard links, symlinks and symlinked directories.

usage: output_guard_test.py BUILD_DIR SCENE_DIR
"""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

BUILD, SCENES = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "sweep"))
from output_guard import check_outputs  # noqa: E402

SWEEP = os.path.join(REPO, "sweep", "pnb_sweep.py")


class OutputGuard(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="pnb_sweep_guard_")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def path(self, name, text=None):
        p = os.path.join(self.dir, name)
        if text is not None:
            os.makedirs(os.path.dirname(p), exist_ok=True)
            with open(p, "w") as f:
                f.write(text)
        return p

    def sweep(self, *args):
        return subprocess.run([sys.executable, SWEEP, "--build", BUILD] + list(args),
                              capture_output=True, text=True)

    def refused(self, result, *names):
        self.assertNotEqual(result.returncode, 0, result.stdout + result.stderr)
        for n in names:
            self.assertIn(n, result.stderr)

    def test_the_rule(self):
        a = self.path("a.txt", "a")
        os.link(a, self.path("hard.txt"))
        os.symlink(self.dir, self.path("here"))
        self.assertIsNotNone(check_outputs([(a, "in")], [(self.path("hard.txt"), "out")]))
        self.assertIsNotNone(check_outputs([(a, "in")], [(self.path("here/a.txt"), "out")]))
        self.assertIsNotNone(check_outputs([], [(self.path("new/x"), "o1"),
                                                (self.path("here/new/x"), "o2")]))
        self.assertIsNone(check_outputs([(a, "in")], [(self.path("b.txt"), "out")]))
        message = check_outputs([(a, "the input")], [(a, "the output")])
        self.assertIn("the output '%s' is the same file as the input '%s'" % (a, a), message)

    def test_plan_and_collect_never_replace_the_sweep_file(self):
        scene = os.path.join(SCENES, "box-room.pnb")
        sweep = self.path("tiny.toml", 'name = "tiny"\nframes = 1\nsize = "64x36"\n'
                          '[axes]\n"shadows.technique" = ["off"]\n'
                          '[[scenes]]\nname = "box-room"\nsource = "%s"\n' % scene)
        before = open(sweep).read()
        self.refused(self.sweep("plan", sweep, "-o", sweep), "the plan (-o)", "the sweep file")
        os.makedirs(self.path("results/none"))
        self.refused(self.sweep("collect", self.path("results"), "--sweep", sweep, "-o", sweep),
                     "the table (-o)", "the sweep file")
        self.assertEqual(open(sweep).read(), before)
        ok = self.sweep("plan", sweep, "-o", self.path("plan.json"))
        self.assertEqual(ok.returncode, 0, ok.stderr)

    def test_convert_refuses_two_inputs_with_one_output(self):
        a = self.path("a/scene.glb")
        b = self.path("b/scene.glb")
        for p in (a, b):
            os.makedirs(os.path.dirname(p))
            shutil.copyfile(os.path.join(SCENES, "box-room.glb"), p)
        listing = self.path("inputs.txt", "a/scene.glb\nb/scene.glb\n")
        self.refused(self.sweep("convert", "--local", listing, "-o", self.path("out")),
                     "the output of '%s'" % b, "the output of '%s'" % a)
        self.assertFalse(os.path.exists(self.path("out/scene.pnb")))


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0]])
