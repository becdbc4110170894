#!/usr/bin/env python3
"""scripts/check-sizes: the repository keeps docs/STYLE.md's size limits (no function over 150
lines, no file over 800, outside tests/), and the checker measures what it claims to: planted
functions and files just over and just at the limits, in the shapes C++ writes them."""
import subprocess
import sys
import unittest

from checker_fixture import REPO, fake_repo, load_script

CHECK, check_sizes = load_script("check-sizes")


def body(lines):
    """A function body of exactly `lines` lines, brace line to brace line."""
    return "{\n" + "    x += 1;\n" * (lines - 2) + "}\n"


class Sizes(unittest.TestCase):
    def test_the_repository_keeps_the_limits(self):
        r = subprocess.run([sys.executable, CHECK, REPO], capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("0 over the limits", r.stdout)

    def test_it_measures_functions_and_files(self):
        d = fake_repo({
            # Free functions: one over, one at the limit.
            "a/free.cpp": "namespace n {\nint over(int x) " + body(151) + "int at(int x) " + body(150) + "}\n",
            # A member defined in its class, a constructor with an initialiser list, a
            # const member out of line; braces in comments and strings do not count, a lambda
            # inside counts towards its function.
            "b/members.h": "struct S {\n    void inClass() " + body(152) + "};\n",
            "b/members.cpp": "S::S() : x(0), y{1} " + body(153) +
                             "int S::get() const {\n    // }}}\n    auto s = \"{{{\";\n" +
                             "    auto f = [&]() " + body(150) + "    return 0;\n}\n",
            "c/long.cpp": "// line\n" * 801,
            "c/ok.cpp": "// line\n" * 800,
            "tests/t.cpp": "void t() " + body(400),  # tests are outside the limits
        })
        over = check_sizes.check(d)
        text = "\n".join(over)
        self.assertIn("a/free.cpp:2: function of 151 lines", text)
        self.assertIn("b/members.h:2: function of 152 lines", text)
        self.assertIn("b/members.cpp:1: function of 153 lines", text)
        self.assertIn("b/members.cpp:154: function of 155 lines", text)  # S::get: its lambda's 150 and 5
        self.assertIn("c/long.cpp: 801 lines", text)
        self.assertEqual(len(over), 5, text)
        r = subprocess.run([sys.executable, CHECK, d], capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn("5 over the limits", r.stdout)


if __name__ == "__main__":
    unittest.main()
