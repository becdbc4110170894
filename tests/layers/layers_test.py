#!/usr/bin/env python3
"""scripts/check-layers: the repository has no arrow against its floors, and the checker sees the
kinds of arrow it claims to (a sideways include, an upward bare include, a sideways CMake link)."""
import subprocess
import sys
import unittest

from checker_fixture import REPO, fake_repo, load_script

CHECK, check_layers = load_script("check-layers")


class Layers(unittest.TestCase):
    def test_the_repository_keeps_its_floors(self):
        r = subprocess.run([sys.executable, CHECK, REPO], capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("0 arrow(s) against the floors", r.stdout)
        # The floors the architecture document draws.
        graph, _ = check_layers.check(REPO)
        self.assertEqual(graph["lighting"], {"format"})
        for middle in ("converter", "player", "reference"):
            self.assertTrue(graph[middle] <= {"cli", "format", "lighting", "shaders"}, (middle, graph[middle]))
        self.assertEqual(graph["judge"] - {"format", "lighting"}, {"player", "reference"})

    def test_it_finds_sideways_upward_and_linked_arrows(self):
        d = fake_repo({
            "format/include/pnb/chunks.h": "",
            "player/math/sh9.h": "",
            "player/include/pnb_player/renderer.h": '#include "pnb/chunks.h"\n',
            "converter/src/env.cpp": '#include "sh9.h"\n#include "pnb/chunks.h"\n',
            "reference/src/t.cpp": '#include "pnb_player/renderer.h"\n',
            "format/src/x.cpp": '#include "pnb_player/renderer.h"\n',
            "player/CMakeLists.txt": "add_library(pnb_player a.cpp)\nadd_library(pnb::player ALIAS pnb_player)\n",
            "reference/CMakeLists.txt": "add_library(pnb_reference b.cpp)\n"
                                        "target_link_libraries(pnb_reference PRIVATE\n  pnb::player) # links\n",
        })
        graph, bad = check_layers.check(d)
        text = "\n".join(bad)
        self.assertIn('converter -> player (floor 2 -> 2): converter/src/env.cpp:1 includes "sh9.h"', text)
        self.assertIn("reference -> player (floor 2 -> 2): reference/src/t.cpp:1", text)
        self.assertIn("format -> player (floor 0 -> 2): format/src/x.cpp:1", text)
        self.assertIn("reference -> player (floor 2 -> 2): reference/CMakeLists.txt: pnb_reference links pnb::player", text)
        self.assertEqual(len(bad), 4, text)  # downward arrows (player -> format) are not reported
        r = subprocess.run([sys.executable, CHECK, d], capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)

    def test_the_renderer_keeps_its_subsystem_floors(self):
        graph, bad = check_layers.check_player(REPO)
        self.assertEqual(bad, [])
        # The frame's shared parts see no subsystem; only the renderer sees them all.
        self.assertTrue(graph["frame"] <= {"gl", "camera"}, graph["frame"])
        self.assertTrue(graph["renderer"] >= {"shadows", "gi", "sky", "lights", "shading", "post"}, graph["renderer"])
        for low in ("gl", "camera"):
            self.assertEqual(graph.get(low, set()), set(), low)

    def test_it_finds_arrows_against_the_renderers_floors(self):
        d = fake_repo({
            "player/src/frame/frame_context.h": '#include "shadows/shadow_maps.h"\n',  # upward
            "player/src/shadows/shadow_maps.h": '#include "frame/frame_context.h"\n',  # downward
            "player/src/shading/pass_forward.cpp": '#include "post/post.h"\n',          # sideways
            "player/src/post/post.h": "",
            "player/src/gi/gi_setup.cpp": '#include "ibl.h"\n',                        # bare, upward
            "player/src/sky/ibl.h": "",
            "player/src/benchmark.cpp": "",                                            # no folder
        })
        _, bad = check_layers.check_player(d)
        text = "\n".join(bad)
        self.assertIn('player/src/frame -> shadows (floor 1 -> 3): player/src/frame/frame_context.h:1', text)
        self.assertIn('player/src/shading -> post (floor 6 -> 6): player/src/shading/pass_forward.cpp:1', text)
        self.assertIn('player/src/gi -> sky (floor 4 -> 5): player/src/gi/gi_setup.cpp:1 includes "ibl.h"', text)
        self.assertIn("player/src/benchmark.cpp is in no subsystem folder", text)
        self.assertEqual(len(bad), 4, text)
        r = subprocess.run([sys.executable, CHECK, d], capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn("4 arrow(s) against the renderer's floors", r.stdout)


if __name__ == "__main__":
    unittest.main()
