#!/usr/bin/env python3
"""Shadow-technique sweep: cost against error, one run per scene (see scripts/bench-shadows).

For each scene, every configuration is played headless along the scene's camera path with
pnb-play --bench --shadow-metrics: GPU frame time (timer queries), the shadow pass, SDSM's
reduction and lighting, shadow draw calls, exact shadow memory, and the error against Embree
ray-traced visibility (misclassified pixels, irradiance-weighted error, mean absolute error,
texel/pixel ratio, flicker).
Shadows-off runs are interleaved through the sweep; each configuration's cost is its mean frame
time over the path divided by that of the nearest off runs before and after it (the machine drifts).

Two error axes, two fronts: misclassified pixels ("how many pixels are wrong") and the
irradiance-weighted error ("how much of the light is wrong", where a grazing wall counts little).
Output (DIR/<scene>/): sweep.csv, sweep.md, pareto.png and pareto_weighted.png (error against
cost with its Pareto front; --error picks which front sweep.md marks first), and
runs/<config>/ (each run's summary.json, frames.csv, quality.csv).
"""
import argparse
import csv
import json
import os
import subprocess
import sys


def configs(quick):
    resolutions = [512, 1024, 2048] if quick else [512, 1024, 2048, 4096]
    cascades = [1, 2, 4] if quick else [1, 2, 4, 8]
    out = []
    for t in ["single", "lispsm"]:
        for r in resolutions:
            out.append(dict(technique=t, cascades=1, resolution=r, filter="poisson", render="layered"))
    for t in ["pssm", "sdsm"]:
        for m in cascades:
            for r in resolutions:
                out.append(dict(technique=t, cascades=m, resolution=r, filter="poisson", render="layered"))
    for t in ["pssm", "sdsm"]:
        for f in ["hardware", "pcss"]:
            out.append(dict(technique=t, cascades=4, resolution=2048, filter=f, render="layered"))
        out.append(dict(technique=t, cascades=4, resolution=2048, filter="poisson", render="multipass"))
    return out


def name_of(c):
    if c["technique"] == "off":
        return "off-%d" % c["index"]
    return "%s-m%d-r%d-%s-%s" % (c["technique"], c["cascades"], c["resolution"], c["filter"], c["render"])


def run(args, scene, c, out_dir):
    cmd = [args.player, scene, "--headless", "--bench", "--frames", str(args.frames), "--fixed-dt",
           "--size", args.size, "--no-plot", "-q", "--out", out_dir,
           "--set", "shadows.technique=" + c["technique"]]
    if c["technique"] != "off":
        cmd += ["--shadow-metrics", str(args.every),
                "--set", "shadows.cascades=%d" % c["cascades"],
                "--set", "shadows.resolution=%d" % c["resolution"],
                "--set", "shadows.filter=" + c["filter"],
                "--set", "shadows.render=" + c["render"]]
    if not args.summarize_only:
        subprocess.run(cmd, check=True)
    with open(os.path.join(out_dir, "summary.json")) as f:
        s = json.load(f)
    row = dict(c)
    row["config"] = name_of(c)
    # Means over the path, not medians: along a fly-through the frame time can change tenfold
    # (flat-city: 280 -> 28 ms), and the median of such a ramp moves with every small shift.
    with open(os.path.join(out_dir, "frames.csv")) as f:
        frames = list(csv.DictReader(f))
    mean = lambda k: sum(float(r[k]) for r in frames) / len(frames) if k in frames[0] else 0.0
    row["frame_ms"] = mean("gpu_total_ms")
    for p in ["shadow", "reduce", "lighting", "gbuffer"]:
        row[p + "_ms"] = mean("gpu_%s_ms" % p)
    row["shadow_draws"] = mean("shadow_draws")
    mem = s["gpu_memory_bytes"]
    row["shadow_mib"] = (mem.get("shadow_maps", 0) + mem.get("shadow_buffers", 0)) / 1048576.0
    q = s.get("quality", {})
    for k in ["misclassified_pct", "false_lit_pct", "false_shadow_pct", "mean_abs_error",
              "weighted_error_pct", "weighted_false_lit_pct", "weighted_false_shadow_pct",
              "flicker_pct", "spurious_flicker_pct"]:
        row[k] = q[k]["mean"] if k in q else ""
    row["texel_ratio_median_c0"] = q["texel_ratio_median_c0"]["mean"] if "texel_ratio_median_c0" in q else ""
    row["texel_ratio_p95_c0"] = q["texel_ratio_p95_c0"]["mean"] if "texel_ratio_p95_c0" in q else ""
    return row


ERRORS = {"misclassified": ("misclassified_pct", "misclassified pixels vs ray-traced truth (%)"),
          "weighted": ("weighted_error_pct", "irradiance-weighted error vs ray-traced truth (%)")}


def pareto(rows, key):
    pts = sorted((r for r in rows if r[key] != ""), key=lambda r: r["cost"])
    front, best = [], float("inf")
    for r in pts:
        if r[key] < best:
            front.append(r)
            best = r[key]
    return front


def plot(rows, front, path, title, key, label):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("bench-shadows: matplotlib missing, no plot", file=sys.stderr)
        return
    colours = {"single": "tab:gray", "lispsm": "tab:purple", "pssm": "tab:blue", "sdsm": "tab:red"}
    markers = {512: "o", 1024: "s", 2048: "^", 4096: "D"}
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for r in rows:
        if r[key] == "":
            continue
        ax.scatter(r["cost"], max(r[key], 1e-3), c=colours[r["technique"]],
                   marker=markers.get(r["resolution"], "x"), s=18 + 10 * r["cascades"], alpha=0.8,
                   edgecolors="k" if r["filter"] != "poisson" or r["render"] != "layered" else "none")
    ax.plot([r["cost"] for r in front], [max(r[key], 1e-3) for r in front], "k--", lw=1,
            label="Pareto front")
    for t, col in colours.items():
        ax.scatter([], [], c=col, label=t)
    for res, m in markers.items():
        ax.scatter([], [], c="w", edgecolors="k", marker=m, label="%d²" % res)
    ax.set_yscale("log")
    ax.set_xlabel("frame time / shadows-off frame time (same run)")
    ax.set_ylabel(label)
    ax.set_title(title + " (marker size: cascades)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--player", required=True)
    ap.add_argument("--scene-dir", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--frames", type=int, default=16)
    ap.add_argument("--every", type=int, default=8)
    ap.add_argument("--size", default="480x270")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--error", choices=sorted(ERRORS), default="misclassified",
                    help="the error whose Pareto front sweep.md marks first (both are plotted)")
    ap.add_argument("--summarize-only", action="store_true",
                    help="re-read the runs already in DIR/<scene>/runs instead of playing them")
    ap.add_argument("scenes", nargs="+")
    args = ap.parse_args()
    for scene in args.scenes:
        scene_file = os.path.join(args.scene_dir, scene + ".pnb")
        out = os.path.join(args.out, scene)
        os.makedirs(out, exist_ok=True)
        plan = []
        for i, c in enumerate(configs(args.quick)):
            if i % 8 == 0:
                plan.append(dict(technique="off", index=i))
            plan.append(c)
        plan.append(dict(technique="off", index=len(plan)))
        rows = []
        for n, c in enumerate(plan):
            print("[%s %d/%d] %s" % (scene, n + 1, len(plan), name_of(c)), flush=True)
            rows.append(run(args, scene_file, c, os.path.join(out, "runs", name_of(c))))
        offs = [i for i, r in enumerate(rows) if r["technique"] == "off"]
        for i, r in enumerate(rows):
            before = max([j for j in offs if j <= i], default=offs[0])
            after = min([j for j in offs if j >= i], default=offs[-1])
            base = (rows[before]["frame_ms"] + rows[after]["frame_ms"]) / 2
            r["off_ms"] = base
            r["cost"] = r["frame_ms"] / base
        rows = [r for r in rows if r["technique"] != "off"] + [r for r in rows if r["technique"] == "off"]
        measured = [r for r in rows if r["technique"] != "off"]
        fronts = {e: pareto(measured, ERRORS[e][0]) for e in ERRORS}
        other = "weighted" if args.error == "misclassified" else "misclassified"
        keys = ["config", "technique", "cascades", "resolution", "filter", "render", "frame_ms", "off_ms",
                "cost", "shadow_ms", "reduce_ms", "lighting_ms", "gbuffer_ms", "shadow_draws", "shadow_mib",
                "misclassified_pct", "false_lit_pct", "false_shadow_pct", "mean_abs_error",
                "weighted_error_pct", "weighted_false_lit_pct", "weighted_false_shadow_pct", "flicker_pct",
                "spurious_flicker_pct", "texel_ratio_median_c0", "texel_ratio_p95_c0"]
        with open(os.path.join(out, "sweep.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys + ["pareto", "pareto_weighted"], extrasaction="ignore")
            w.writeheader()
            for r in rows:
                w.writerow(dict(r, pareto=r in fronts["misclassified"], pareto_weighted=r in fronts["weighted"]))
        with open(os.path.join(out, "sweep.md"), "w") as f:
            f.write("| config | ms | cost | shadow ms | reduce ms | draws | MiB | misclass. %% | weighted %% | MAE | "
                    "spurious flicker %% | texel/px c0 | Pareto %s | Pareto %s |\n" % (args.error, other))
            f.write("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|:-:|:-:|\n")
            fmt = lambda v, p=2: ("%.*f" % (p, v)) if isinstance(v, float) else str(v)
            for r in rows:
                if r["technique"] == "off":
                    continue
                f.write("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n" % (
                    r["config"], fmt(r["frame_ms"], 1), fmt(r["cost"]), fmt(r["shadow_ms"], 1),
                    fmt(r["reduce_ms"], 2), fmt(float(r["shadow_draws"]), 0), fmt(r["shadow_mib"], 0),
                    fmt(r["misclassified_pct"], 3), fmt(r["weighted_error_pct"], 3),
                    fmt(r["mean_abs_error"], 4), fmt(r["spurious_flicker_pct"], 3),
                    fmt(r["texel_ratio_median_c0"], 2),
                    "*" if r in fronts[args.error] else "", "*" if r in fronts[other] else ""))
        for e, png in [("misclassified", "pareto.png"), ("weighted", "pareto_weighted.png")]:
            plot(measured, fronts[e], os.path.join(out, png), scene, *ERRORS[e])
        print("wrote %s/sweep.csv, sweep.md, pareto.png, pareto_weighted.png" % out)


if __name__ == "__main__":
    main()
