#!/usr/bin/env python3
"""GI scorecard: every technique against both indirect truths (see scripts/bench-gi --scorecard).

For each scene (converted with pnb-convert --gi --sky) and technique -- the LPV (the default), the
probes with one bounce (gi.bounces=1) and the probes with several (gi.bounces=N) -- one
pnb-judge --bench --camera 0 --frames 1 --gi-metrics 1 --gi-lights sun run per truth: the
one-bounce truth (--gi-bounces 1, what the techniques used to be judged against) and the
converged one (--gi-bounces converged: unlimited diffuse bounces with Russian roulette). Columns:
RMSE over the best constant's (the truth's noise removed), energy ratio and correlation, per
truth; and the GI cost: the median GPU ms of the GI passes over --cost-frames frames with the
probes updated every frame (gi.probe_cache=false: what a moving sun costs; cached probes cost
only the look-up, which is in the lighting pass and not counted here).

Output: DIR/scorecard.csv and DIR/scorecard.md (and the runs under DIR/runs/).
"""
import argparse
import csv
import json
import os
import subprocess
import sys

TRUTHS = [("one", "1"), ("converged", "converged")]
GI_STAGES = ("gi_rsm", "gi_rsm_glass", "gi_inject", "gi_geometry", "gi_propagate", "gi_probes")


def techniques(bounces):
    return [("lpv", ["--set", "gi.technique=lpv"]),
            ("probes, 1 bounce", ["--set", "gi.technique=probes", "--set", "gi.bounces=1"]),
            (f"probes, {bounces} bounces", ["--set", "gi.technique=probes", "--set", f"gi.bounces={bounces}"])]


def run(cmd, quiet=True):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       env=dict(os.environ, EGL_LOG_LEVEL="fatal"))
    if r.returncode != 0:
        sys.exit(f"scorecard: {' '.join(cmd)} failed:\n{r.stdout[-3000:]}")
    return r.stdout


def container(bin_dir, scene, out):
    """SCENE.pnb converted with GI and the sky (its .glb from the build, else pnb-make-scene)."""
    glb = os.path.join(bin_dir, "scenes", scene + ".glb")
    if not os.path.exists(glb):
        glb = os.path.join(out, scene + ".glb")
        run([os.path.join(bin_dir, "assets_src", "pnb-make-scene"), scene, glb])
    pnb = os.path.join(out, scene + ".pnb")
    run([os.path.join(bin_dir, "converter", "pnb-convert"), glb, "-o", pnb, "--gi", "--sky", "-j", "1"])
    return pnb


def quality(bin_dir, pnb, settings, truth, args, out):
    run([os.path.join(bin_dir, "judge", "pnb-judge"), pnb, "--headless", "--bench", "--camera", "0",
         "--frames", "1", "--size", args.size, "--gi-metrics", "1", "--gi-samples", str(args.samples),
         "--gi-lights", "sun", "--gi-bounces", truth, "--out", out] + settings)
    with open(os.path.join(out, "quality.csv")) as f:
        row = next(csv.DictReader(f))
    return {k: float(row["gi_" + k]) for k in ("rmse_over_constant", "energy_ratio", "correlation")}


def cost(bin_dir, pnb, settings, args, out):
    run([os.path.join(bin_dir, "player", "pnb-play"), pnb, "--headless", "--bench", "--camera", "0",
         "--frames", str(args.cost_frames), "--size", args.size, "--set", "gi.probe_cache=false",
         "--out", out] + settings)
    with open(os.path.join(out, "summary.json")) as f:
        gpu = json.load(f)["gpu_ms"]
    return sum(v["median_ms"] for k, v in gpu.items() if k in GI_STAGES)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scenes", nargs="*", default=["box-room", "atrium", "street-canyon", "colour-room"])
    p.add_argument("--bin", default="build/release")
    p.add_argument("--out", default="out/bench/gi/scorecard")
    p.add_argument("--size", default="320x180")
    p.add_argument("--samples", type=int, default=128, help="truth rays per pixel (default 128)")
    p.add_argument("--bounces", type=int, default=4, help="the probes' gi.bounces for the multi-bounce row")
    p.add_argument("--cost-frames", type=int, default=5)
    p.add_argument("--techniques", default="lpv,probes1,probesN",
                   help="comma-separated subset of lpv, probes1, probesN (quick iterations)")
    p.add_argument("--truths", default="one,converged", help="comma-separated subset of one, converged")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="an extra player setting for every technique (repeatable)")
    p.add_argument("--no-cost", action="store_true", help="skip the GI cost runs (quick iterations)")
    args = p.parse_args()
    keys = args.techniques.split(",")
    truths = [t for t in TRUTHS if t[0] in args.truths.split(",")]
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for scene in args.scenes:
        pnb = container(args.bin, scene, args.out)
        for key, (name, settings) in zip(("lpv", "probes1", "probesN"), techniques(args.bounces)):
            if key not in keys:
                continue
            settings = settings + [a for kv in args.set for a in ("--set", kv)]
            row = {"scene": scene, "technique": name}
            for label, truth in truths:
                runs = os.path.join(args.out, "runs", scene, name.replace(" ", "_").replace(",", ""), label)
                os.makedirs(runs, exist_ok=True)
                for k, v in quality(args.bin, pnb, settings, truth, args, runs).items():
                    row[f"{label}_{k}"] = v
            runs = os.path.join(args.out, "runs", scene, name.replace(" ", "_").replace(",", ""), "cost")
            os.makedirs(runs, exist_ok=True)
            row["gi_ms"] = float("nan") if args.no_cost else cost(args.bin, pnb, settings, args, runs)
            rows.append(row)
            print(f"{scene:14s} {name:18s} " + "  ".join(
                f"{label}: {row[label + '_rmse_over_constant']:.3f} / {row[label + '_energy_ratio']:.3f} / "
                f"{row[label + '_correlation']:.3f}" for label, _ in truths) + f"  GI {row['gi_ms']:.1f} ms",
                flush=True)
    with open(os.path.join(args.out, "scorecard.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(args.out, "scorecard.md"), "w") as f:
        f.write(f"GI scorecard ({args.size}, camera 0, truth {args.samples} rays, sun only; "
                "RMSE / best constant, energy, correlation against each truth; GI ms: median GPU ms "
                "of the GI passes, probes updated every frame)\n\n")
        f.write("| scene | technique | " + "".join(
            f"{'one bounce' if label == 'one' else 'converged'}: RMSE/const | energy | corr. | " for label, _ in truths)
            + "GI ms |\n|---|---|" + "---|---|---|" * len(truths) + "---|\n")
        for r in rows:
            f.write(f"| {r['scene']} | {r['technique']} | " + " | ".join(
                f"{r[label + '_rmse_over_constant']:.3f} | {r[label + '_energy_ratio']:.3f} | "
                f"{r[label + '_correlation']:.3f}" for label, _ in truths) + f" | {r['gi_ms']:.1f} |\n")
    print(f"wrote {args.out}/scorecard.md")


if __name__ == "__main__":
    main()
