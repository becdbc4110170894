#!/usr/bin/env python3
"""GI sweep: the LPV's cost against its error, one run per scene (see scripts/bench-gi).

Each scene is converted with GI (pnb-convert --gi, its camera path if it has one) and played
headless along its path with pnb-play --bench --gi-metrics for every configuration of cells x
iterations x cascades x RSM resolution, plus the seed's configurations (thesis tables 7.2-7.7)
and their geometry-volume-off twins. GI-off runs are interleaved; a configuration's cost is its
mean frame time over the path against the mean of the nearest GI-off runs before and after it
(the machine drifts). Per stage (GPU timer queries): RSM, injection, geometry (camera surfels and
the resolve), propagation, and the look-up (lighting time minus the GI-off runs' lighting time).
Error (against the Embree one-bounce truth, sun only: what the LPV models): relative RMSE of
indirect luminance, energy ratio, leak, flicker, and the truth's own noise.

Output (DIR/<scene>/): sweep.csv, sweep.md (all runs, the Pareto front, the seed's
configurations beside its GTX 960 figures, and the ratios the issue sets), pareto.png, runs/.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

# Thesis (seed 004) GTX 960 figures, Crytek Sponza, RSM 256^2: (init ms, propagation ms).
SEED = {(1, 32, 8): (0.376, 3.370), (3, 32, 8): (1.000, 8.754), (3, 32, 12): (1.000, 13.881),
        (1, 64, 8): (0.797, 15.642)}
STAGES = ["gi_rsm", "gi_inject", "gi_geometry", "gi_propagate", "lighting", "shadow", "gbuffer"]


def configs(quick):
    cells = [16, 32] if quick else [16, 32, 64]
    iterations = [4, 8] if quick else [4, 8, 16]
    cascades = [1, 3] if quick else [1, 2, 3]
    rsm = [256] if quick else [128, 256, 512]
    out = [dict(cascades=c, cells=n, iterations=i, rsm=r, occlusion=True)
           for n in cells for i in iterations for c in cascades for r in rsm]
    for (c, n, i) in SEED:
        for occ in (True, False):
            cfg = dict(cascades=c, cells=n, iterations=i, rsm=256, occlusion=occ)
            if cfg not in out:
                out.append(cfg)
    return out


def name_of(c):
    if c.get("off"):
        return "off-%d" % c["index"]
    return "c%d-n%d-i%d-r%d%s" % (c["cascades"], c["cells"], c["iterations"], c["rsm"],
                                  "" if c["occlusion"] else "-noocc")


def run(args, scene_file, c, out_dir):
    cmd = [args.player, scene_file, "--headless", "--bench", "--frames", str(args.frames), "--fixed-dt",
           "--size", args.size, "--no-plot", "-q", "--out", out_dir]
    if c.get("off"):
        cmd += ["--set", "gi.enabled=false"]
    else:
        cmd += ["--set", "gi.enabled=true", "--set", "gi.cascades=%d" % c["cascades"],
                "--set", "gi.cells=%d" % c["cells"], "--set", "gi.iterations=%d" % c["iterations"],
                "--set", "gi.rsm_resolution=%d" % c["rsm"],
                "--set", "gi.occlusion=%s" % ("true" if c["occlusion"] else "false"),
                "--gi-metrics", str(args.every), "--gi-samples", str(args.samples)]
    if not args.summarize_only:
        subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
    with open(os.path.join(out_dir, "frames.csv")) as f:
        frames = list(csv.DictReader(f))[1:]  # frame 0 compiles programs: left out
    mean = lambda k: sum(float(r[k]) for r in frames) / len(frames) if frames and k in frames[0] else 0.0
    row = dict(c)
    row["config"] = name_of(c)
    row["frame_ms"] = mean("gpu_total_ms")
    for s in STAGES:
        row[s + "_ms"] = mean("gpu_%s_ms" % s)
    with open(os.path.join(out_dir, "summary.json")) as f:
        summary = json.load(f)
    row["gi_mib"] = summary["gpu_memory_bytes"].get("gi", 0) / 1048576.0
    row["size"] = "%dx%d" % (summary["run"]["width"], summary["run"]["height"])
    row["frames"] = summary["run"]["frames"]
    words = summary["run"]["command"].split()
    option = lambda name, default: words[words.index(name) + 1] if name in words else default
    row["samples"], row["every"] = option("--gi-samples", "?"), option("--gi-metrics", "?")
    q = summary.get("quality", {})
    for k in ["gi_rmse_pct", "gi_reference_noise_pct", "gi_corrected_rmse_pct", "gi_energy_ratio", "gi_red_ratio", "gi_green_ratio",
              "gi_blue_ratio", "gi_leak_pct", "gi_flicker_pct"]:
        row[k] = q[k]["mean"] if k in q else ""
    if row["gi_corrected_rmse_pct"] == "" and row["gi_rmse_pct"] != "":  # runs of an older pnb-play
        row["gi_corrected_rmse_pct"] = max(0.0, row["gi_rmse_pct"] ** 2 - row["gi_reference_noise_pct"] ** 2) ** 0.5
    return row


ERROR = "gi_corrected_rmse_pct" # the player's error with the truth's Monte-Carlo noise taken out


def pareto(rows):
    # Cheapest first; a configuration joins the front if it beats every cheaper one by more than
    # half a point (ties within the truth's noise are not progress).
    front, best = [], float("inf")
    for r in sorted((r for r in rows if r[ERROR] != ""), key=lambda r: r["cost"]):
        if r[ERROR] < best - 0.5:
            front.append(r)
            best = r[ERROR]
    return front


def plot(rows, front, path, title):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("bench-gi: matplotlib missing, no plot", file=sys.stderr)
        return
    colours = {1: "tab:blue", 2: "tab:orange", 3: "tab:red"}
    markers = {16: "o", 32: "s", 64: "^"}
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for r in rows:
        ax.scatter(r["cost"], r[ERROR], c=colours.get(r["cascades"], "k"), marker=markers.get(r["cells"], "x"),
                   s=10 + 2 * r["iterations"], alpha=0.8, edgecolors="none" if r["occlusion"] else "k")
    ax.plot([r["cost"] for r in front], [r[ERROR] for r in front], "k--", lw=1, label="Pareto front")
    for c, col in colours.items():
        ax.scatter([], [], c=col, label="%d cascade%s" % (c, "s" if c > 1 else ""))
    for n, m in markers.items():
        ax.scatter([], [], c="w", edgecolors="k", marker=m, label="%d³" % n)
    ax.set_xlabel("frame time / GI-off frame time (same run)")
    ax.set_ylabel("relative RMSE of indirect light vs ray-traced truth, noise removed (%)")
    ax.set_title(title + " (marker size: iterations; black edge: no occlusion)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def convert(args, scene, out):
    source = os.path.join(args.scene_dir, scene + ".glb")
    target = os.path.join(out, scene + "-gi.pnb")
    cmd = [args.converter, source, "-o", target, "--gi"]
    path = os.path.join(args.paths, scene + ".json")
    if os.path.exists(path):
        cmd += ["--path", path]
    if not args.summarize_only:
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return target


def find(rows, cascades, cells, iterations, rsm=256, occlusion=True):
    for r in rows:
        if (r["cascades"], r["cells"], r["iterations"], r["rsm"], r["occlusion"]) == (
                cascades, cells, iterations, rsm, occlusion):
            return r
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--player", required=True)
    ap.add_argument("--converter", required=True)
    ap.add_argument("--scene-dir", required=True)
    ap.add_argument("--paths", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--frames", type=int, default=9)
    ap.add_argument("--every", type=int, default=4)
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--size", default="480x270")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--summarize-only", action="store_true")
    ap.add_argument("scenes", nargs="+")
    args = ap.parse_args()
    for scene in args.scenes:
        out = os.path.join(args.out, scene)
        os.makedirs(out, exist_ok=True)
        scene_file = convert(args, scene, out)
        plan = []
        for i, c in enumerate(configs(args.quick)):
            if i % 6 == 0:
                plan.append(dict(off=True, index=i))
            plan.append(c)
        plan.append(dict(off=True, index=len(plan)))
        rows = []
        for n, c in enumerate(plan):
            print("[%s %d/%d] %s" % (scene, n + 1, len(plan), name_of(c)), flush=True)
            rows.append(run(args, scene_file, c, os.path.join(out, "runs", name_of(c))))
        offs = [i for i, r in enumerate(rows) if r.get("off")]
        for i, r in enumerate(rows):
            before = max([j for j in offs if j <= i], default=offs[0])
            after = min([j for j in offs if j >= i], default=offs[-1])
            r["off_ms"] = (rows[before]["frame_ms"] + rows[after]["frame_ms"]) / 2
            r["cost"] = r["frame_ms"] / r["off_ms"]
            r["lookup_ms"] = r["lighting_ms"] - (rows[before]["lighting_ms"] + rows[after]["lighting_ms"]) / 2
            r["gi_ms"] = sum(r[s + "_ms"] for s in ["gi_rsm", "gi_inject", "gi_geometry", "gi_propagate"]) + r["lookup_ms"]
        measured = [r for r in rows if not r.get("off")]
        front = pareto(measured)
        keys = ["config", "cascades", "cells", "iterations", "rsm", "occlusion", "frame_ms", "off_ms", "cost",
                "gi_ms", "gi_rsm_ms", "gi_inject_ms", "gi_geometry_ms", "gi_propagate_ms", "lookup_ms", "gi_mib",
                "gi_rmse_pct", "gi_reference_noise_pct", "gi_corrected_rmse_pct", "gi_energy_ratio", "gi_red_ratio",
                "gi_green_ratio",
                "gi_blue_ratio", "gi_leak_pct", "gi_flicker_pct"]
        with open(os.path.join(out, "sweep.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys + ["pareto"], extrasaction="ignore")
            w.writeheader()
            for r in measured:
                w.writerow(dict(r, pareto=r in front))
        fmt = lambda v, p=2: ("%.*f" % (p, v)) if isinstance(v, float) else str(v)
        with open(os.path.join(out, "sweep.md"), "w") as f:
            size = measured[0]["size"] if measured else args.size
            f.write("%s, %s, %s frames, truth %s rays/pixel every %s frames (llvmpipe: read ratios)\n\n" % (
                scene, size, measured[0]["frames"], measured[0]["samples"], measured[0]["every"]))
            f.write("| config | cost | GI ms | RSM | inject | geometry | propagate | look-up | MiB | RMSE % | "
                    "noise % | RMSE w/o noise % | energy | R/G/B | leak % | flicker % | Pareto |\n")
            f.write("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|:-:|\n")
            for r in measured:
                f.write("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s/%s/%s | %s | %s | %s |\n" % (
                    r["config"], fmt(r["cost"]), fmt(r["gi_ms"], 1), fmt(r["gi_rsm_ms"], 1), fmt(r["gi_inject_ms"], 1),
                    fmt(r["gi_geometry_ms"], 1), fmt(r["gi_propagate_ms"], 1), fmt(r["lookup_ms"], 1),
                    fmt(r["gi_mib"], 1), fmt(r["gi_rmse_pct"], 1), fmt(r["gi_reference_noise_pct"], 1),
                    fmt(r["gi_corrected_rmse_pct"], 1),
                    fmt(r["gi_energy_ratio"]), fmt(r["gi_red_ratio"]), fmt(r["gi_green_ratio"]), fmt(r["gi_blue_ratio"]),
                    fmt(r["gi_leak_pct"], 1), fmt(r["gi_flicker_pct"], 1), "*" if r in front else ""))
            f.write("\nThe seed's configurations (thesis: GTX 960, Crytek Sponza, RSM 256²; init = injection "
                    "with geometry):\n\n| config | inject+geometry ms | propagate ms | thesis init | thesis propagate "
                    "| RMSE w/o noise % |\n|---|--:|--:|--:|--:|--:|\n")
            for (c, n, i), (ti, tp) in SEED.items():
                r = find(measured, c, n, i)
                if r:
                    f.write("| %d×%d³ %d it. | %s | %s | %.3f | %.3f | %s |\n" % (
                        c, n, i, fmt(r["gi_inject_ms"] + r["gi_geometry_ms"], 1), fmt(r["gi_propagate_ms"], 1), ti, tp,
                        fmt(r[ERROR], 1)))
            a, b = find(measured, 3, 32, 8), find(measured, 1, 64, 8)
            noocc = find(measured, 3, 32, 8, occlusion=False)
            f.write("\nRatios (same run):\n\n")
            if a and b:
                f.write("- 3×32³ / 1×64³ GI cost: %.2f (target ≤ 0.45; thesis 0.56)\n" % (a["gi_ms"] / b["gi_ms"]))
            if a and noocc and noocc["gi_propagate_ms"] > 0:
                f.write("- geometry-volume occlusion adds %.0f %% to propagation (target ≤ 15 %%; thesis 20 %%): "
                        "the faces' transmittance is computed once per frame; with the geometry stage "
                        "(camera surfels, resolve, transmittance) it adds %.0f %% to all of GI\n" % (
                            100 * (a["gi_propagate_ms"] / noocc["gi_propagate_ms"] - 1),
                            100 * (a["gi_ms"] / noocc["gi_ms"] - 1)))
            lin = [(r["cells"] ** 3 * r["iterations"] * r["cascades"], r["gi_propagate_ms"]) for r in measured
                   if r["occlusion"] and r["rsm"] == 256]
            if len(lin) > 2:
                per = sorted(ms / work * 1e6 for work, ms in lin if work > 0)
                f.write("- propagation per million cell-iterations: min %.1f, median %.1f, max %.1f ms "
                        "(linear if these agree)\n" % (per[0], per[len(per) // 2], per[-1]))
            d = find(measured, 3, 32, 8)
            if d:
                f.write("- the default (3×32³, 8 it., RSM 256²) adds %.0f %% to the frame at %s\n" % (
                    100 * (d["cost"] - 1), size))
        plot(measured, front, os.path.join(out, "pareto.png"), scene)
        print("wrote %s/sweep.csv, sweep.md, pareto.png" % out)


if __name__ == "__main__":
    main()
