#!/usr/bin/env python3
"""The frame cost of the probes with bounces against the LPV (issue 40's question: should the
default GI technique become the probes?).

Per scene (the containers bench/gi/scorecard.py converted: DIR/SCENE.pnb, or converts them), in
--rounds interleaved rounds (so that the shared machine's load falls on every configuration alike):
pnb-play SCENE.pnb --headless --bench --camera 0 --frames F --size WxH with
  lpv                       gi.technique=lpv (the default; it propagates every frame),
  probes N, static sun      gi.technique=probes gi.bounces=N (gi.probe_cache on: after the first
                            frame only the look-up runs),
  probes N, turning sun     the same with gi.probe_cache=false (RSM, VPLs, gather and N - 1
                            bounce passes every frame: what a sun that moves every frame costs).
The figures per run: the median GPU ms of a whole frame (summary.json's gpu_ms.total) and of
the GI passes (as scorecard.py's GI ms); per configuration the median over the rounds. Output: DIR/frame_cost.md and .csv.
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scorecard import GI_STAGES, container, run  # noqa: E402


def configs(bounces):
    """lpv, then per bounce count the turning sun, the first one's static sun too (a static sun
    costs the look-up alone, whatever the count)."""
    out = [("lpv", ["--set", "gi.technique=lpv"])]
    for i, n in enumerate(bounces):
        probes = ["--set", "gi.technique=probes", "--set", f"gi.bounces={n}"]
        if i == 0:
            out.append((f"probes {n}, static sun", probes + ["--set", "gi.probe_cache=true"]))
        out.append((f"probes {n}, turning sun", probes + ["--set", "gi.probe_cache=false"]))
    return out


def frame_ms(bin_dir, pnb, settings, args, out):
    run([os.path.join(bin_dir, "player", "pnb-play"), pnb, "--headless", "--bench", "--camera", "0",
         "--frames", str(args.frames), "--size", args.size, "--out", out] + settings)
    with open(os.path.join(out, "summary.json")) as f:
        gpu = json.load(f)["gpu_ms"]
    return gpu["total"]["median_ms"], sum(v["median_ms"] for k, v in gpu.items() if k in GI_STAGES)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scenes", nargs="*", default=["box-room", "atrium", "street-canyon", "colour-room"])
    p.add_argument("--bin", default="build/release")
    p.add_argument("--out", default="out/bench/gi/frame_cost")
    p.add_argument("--size", default="320x180")
    p.add_argument("--frames", type=int, default=9)
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--bounces", default="4", help="the probes' gi.bounces, comma-separated (e.g. 4,8)")
    args = p.parse_args()
    args.bounces = [int(b) for b in args.bounces.split(",")]
    os.makedirs(args.out, exist_ok=True)
    pnbs = {s: (os.path.join(args.out, s + ".pnb") if os.path.exists(os.path.join(args.out, s + ".pnb"))
                else container(args.bin, s, args.out)) for s in args.scenes}
    times = {}
    for r in range(args.rounds):
        for scene in args.scenes:
            for i, (name, settings) in enumerate(configs(args.bounces)):
                out = os.path.join(args.out, "runs", scene, f"{i}_round{r}")
                os.makedirs(out, exist_ok=True)
                frame, gi = frame_ms(args.bin, pnbs[scene], settings, args, out)
                times.setdefault((scene, name), []).append(frame)
                times.setdefault((scene, name, "gi"), []).append(gi)
    names = [n for n, _ in configs(args.bounces)]
    rows = []
    for scene in args.scenes:
        lpv = statistics.median(times[(scene, names[0])])
        row = {"scene": scene}
        for n in names:
            row[n] = statistics.median(times[(scene, n)])
            row[n + " / lpv"] = row[n] / lpv
            row[n + " GI"] = statistics.median(times[(scene, n, "gi")])
        rows.append(row)
        print(f"{scene:14s} " + "  ".join(f"{n}: {row[n]:.1f} ms ({row[n + ' / lpv']:.2f} x, GI {row[n + ' GI']:.1f})"
                                          for n in names), flush=True)
    with open(os.path.join(args.out, "frame_cost.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(args.out, "frame_cost.md"), "w") as f:
        f.write(f"Frame cost ({args.size}, camera 0, {args.frames} frames, median GPU ms of a frame "
                f"(its ratio to the LPV's; GI: the GI passes' ms), median of {args.rounds} interleaved rounds)\n\n| scene | " + " | ".join(names) +
                " |\n|---|" + "---|" * len(names) + "\n")
        for row in rows:
            f.write(f"| {row['scene']} | " + " | ".join(
                f"{row[n]:.1f} ({row[n + ' / lpv']:.2f} x; GI {row[n + ' GI']:.1f})" for n in names) + " |\n")
    print(f"wrote {args.out}/frame_cost.md")


if __name__ == "__main__":
    main()
