#!/usr/bin/env python3
"""Moving scenes benchmark (issue 42; scripts/bench-anim runs it).

crowd (pnb-make-scene crowd --count N, for each N): converted with the overview camera path
(assets_src/paths/crowd.json), then pnb-play --headless --bench at --size (480x270; opaque
materials: deferred) along that path with a fixed time step (the path and the clip advance
together), animated (--set anim.enabled=true) against frozen in the bind pose
(--set anim.enabled=false), in --rounds rounds whose order alternates (in-round ratios are
steadier than absolute times on a shared machine). Figures: the median frame time (frame_ms, the
frames after the first) and GPU total of each, their ratios animated / frozen, and the skinning
pass's own GPU time (the frames.csv column deform_ms or gpu_deform_ms; blank where the player
writes none).

moving-light (pnb-make-scene moving-light, converted with --gi): at camera 0 over the clip (4 s
in --ml-frames frames), per GI technique (gi.technique=lpv, probes), animated against frozen:
  - pnb-judge --gi-metrics/--shadow-metrics/--frame-metrics M on both: the indirect light's
    error against the Embree truth (gi_rmse_pct, gi_rmse_over_constant), the sun shadows'
    misclassified pixels, the whole frame's LDR-FLIP, the judge's own flicker figures (the view
    1/60 s later); ratios animated / frozen;
  - pnb-play --bench: the GI passes' GPU time per frame (the sum of the gpu_gi_* columns: the
    LPV's RSM, injection, geometry and propagation, or the probes' update), median;
  - temporal stability (animated, technique lpv): frames 0..K-1 dumped by pnb-play (--dump
    color,position --frame k) and each traced whole by pnb-reference --whole-frame (the same
    seed every frame, so a static pixel's noise repeats): the mean absolute frame-to-frame change
    of the player's LDR images against that of the truth's, over all pixels and over the pixels
    where the truth changes little (< 2/255, blurred): where it is about the truth's noise, the
    player's change there is its own flicker or lag.

The animation is reported absent (anim_present = false; animated and frozen then run the same
container the same way) when pnb-play does not know anim.enabled or pnb-convert reports the
clips or skins as not rendered: the script is written to the final interface and runs before
both exist.

Output: OUT/anim.csv (one row per scene, count or technique, and state), OUT/summary.md (the
tables), OUT/scenes/ (the .glb, .pnb and conversion logs), OUT/runs/ (every run's files).
"""
import argparse
import csv
import json
import math
import os
import statistics
import subprocess
import sys

COLUMNS = ["scene", "state", "count", "technique", "triangles", "anim_present", "size", "frames",
           "frame_ms", "frame_ratio", "gpu_ms", "gpu_ratio", "deform_ms",
           "gi_rmse_pct", "gi_rmse_over_constant", "gi_ratio", "misclassified_pct", "shadow_ratio",
           "frame_flip_ldr", "flip_ratio", "flicker_pct", "gi_flicker_pct", "gi_ms",
           "image_change", "truth_change", "change_ratio", "image_change_static",
           "truth_change_static"]
NAN = float("nan")
ENV = dict(os.environ, EGL_LOG_LEVEL="fatal")


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=ENV)
    if r.returncode != 0:
        sys.exit(f"bench-anim: {' '.join(cmd)} failed ({r.returncode}):\n{r.stdout[-3000:]}")
    return r.stdout


class Tools:
    def __init__(self, build):
        self.make = os.path.join(build, "assets_src", "pnb-make-scene")
        self.convert = os.path.join(build, "converter", "pnb-convert")
        self.play = os.path.join(build, "player", "pnb-play")
        self.judge = os.path.join(build, "judge", "pnb-judge")
        self.reference = os.path.join(build, "reference", "pnb-reference")
        for t in (self.make, self.convert, self.play, self.judge, self.reference):
            if not os.path.exists(t):
                sys.exit(f"bench-anim: {t} is not built")
        listing = run([self.play, "--list-settings"])
        self.anim_setting = any(line.split()[0] == "anim.enabled" for line in listing.splitlines() if line.split())


def make_container(tools, out, name, make_args, convert_args):
    """OUT/scenes/NAME.pnb from pnb-make-scene; True when the container keeps the animation."""
    scenes = os.path.join(out, "scenes")
    os.makedirs(scenes, exist_ok=True)
    glb, pnb = os.path.join(scenes, name + ".glb"), os.path.join(scenes, name + ".pnb")
    run([tools.make] + make_args + [glb])
    log = run([tools.convert, glb, "-o", pnb, "-j", "1"] + convert_args)
    with open(os.path.join(scenes, name + ".convert.log"), "w") as f:
        f.write(log)
    dropped = any(("not rendered: animations" in line or "not rendered: skins" in line
                   or "not rendered: morph" in line) for line in log.splitlines())
    return pnb, tools.anim_setting and not dropped


def anim_set(tools, animated):
    return ["--set", f"anim.enabled={'true' if animated else 'false'}"] if tools.anim_setting else []


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def num(row, key):
    try:
        return float(row[key])
    except (KeyError, TypeError, ValueError):
        return NAN


def median(values):
    values = [v for v in values if not math.isnan(v)]
    return statistics.median(values) if values else NAN


def mean(values):
    values = [v for v in values if not math.isnan(v)]
    return sum(values) / len(values) if values else NAN


def ratio(a, b):
    return a / b if b and not math.isnan(a) and not math.isnan(b) else NAN


def deform_ms(frames, summary):
    """The skinning/morph pass's median GPU ms: frames.csv deform_ms or gpu_deform_ms, else
    summary.json gpu_ms.deform; NaN where the player measures none."""
    for key in ("deform_ms", "gpu_deform_ms"):
        if frames and key in frames[0]:
            return median([num(r, key) for r in frames[1:] or frames])
    stage = summary.get("gpu_ms", {}).get("deform")
    return stage["median_ms"] if stage else NAN


def gi_ms(frames):
    """Median over frames (after the first) of the GI passes' GPU ms (every gpu_gi_* column)."""
    if not frames:
        return NAN
    keys = [k for k in frames[0] if k.startswith("gpu_gi_")]
    if not keys:
        return 0.0
    return median([sum(num(r, k) for k in keys) for r in frames[1:] or frames])


# [SECTION] crowd -----------------------------------------------------------------------------


def bench_crowd(tools, args, rows):
    with open(os.path.join(args.repo, "assets_src", "paths", "crowd.json")) as f:
        path = json.load(f)
    duration = max(k["time"] for k in path["keys"])
    dt = duration / args.frames
    for n in args.counts:
        name = f"crowd-{n}"
        pnb, present = make_container(tools, args.out, name, ["crowd", "--count", str(n)],
                                      ["--path", os.path.join(args.repo, "assets_src", "paths", "crowd.json")])
        per = {True: [], False: []}
        deform, triangles = [], NAN
        for r in range(args.rounds):
            for animated in ((True, False) if r % 2 == 0 else (False, True)):
                d = os.path.join(args.out, "runs", name, f"{'animated' if animated else 'frozen'}-{r}")
                os.makedirs(d, exist_ok=True)
                run([tools.play, pnb, "--headless", "--bench", "--size", args.size, "--frames",
                     str(args.frames), "--fixed-dt", f"{dt:.6f}", "--no-plot", "-q", "--out", d]
                    + anim_set(tools, animated))
                frames = read_csv(os.path.join(d, "frames.csv"))
                with open(os.path.join(d, "summary.json")) as f:
                    summary = json.load(f)
                steady = frames[1:] or frames
                per[animated].append((median([num(x, "frame_ms") for x in steady]),
                                      median([num(x, "gpu_total_ms") for x in steady])))
                triangles = max(num(x, "triangles") for x in frames)
                if animated:
                    deform.append(deform_ms(frames, summary))
        figures = {s: (median([a for a, _ in per[s]]), median([g for _, g in per[s]])) for s in per}
        for animated in (True, False):
            frame, gpu = figures[animated]
            rows.append({"scene": "crowd", "state": "animated" if animated else "frozen", "count": n,
                         "triangles": int(triangles) if not math.isnan(triangles) else "",
                         "anim_present": present, "size": args.size, "frames": args.frames,
                         "frame_ms": frame, "frame_ratio": ratio(frame, figures[False][0]),
                         "gpu_ms": gpu, "gpu_ratio": ratio(gpu, figures[False][1]),
                         "deform_ms": median(deform) if animated else NAN})
        print(f"crowd {n:5d}: animated {figures[True][0]:8.2f} ms, frozen {figures[False][0]:8.2f} ms, "
              f"ratio {ratio(figures[True][0], figures[False][0]):.3f}, deform {median(deform):.3f} ms"
              + ("" if present else "  (animation absent)"), flush=True)


# [SECTION] moving-light ----------------------------------------------------------------------


def quality(tools, args, pnb, settings, d):
    run([tools.judge, pnb, "--headless", "--bench", "--camera", "0", "--size", args.ml_size,
         "--frames", str(args.ml_frames), "--fixed-dt", f"{args.ml_dt:.6f}", "--gi-metrics",
         str(args.every), "--shadow-metrics", str(args.every), "--frame-metrics", str(args.every),
         "--gi-samples", str(args.gi_samples), "--frame-samples", str(args.frame_samples),
         "--frame-time-limit", str(args.frame_time_limit), "--no-plot", "-q", "--out", d] + settings)
    q = read_csv(os.path.join(d, "quality.csv"))
    keys = ("gi_rmse_pct", "gi_rmse_over_constant", "misclassified_pct", "frame_flip_ldr",
            "flicker_pct", "gi_flicker_pct")
    return {k: mean([num(r, k) for r in q]) for k in keys}


def cost(tools, args, pnb, settings, d):
    run([tools.play, pnb, "--headless", "--bench", "--camera", "0", "--size", args.ml_size,
         "--frames", str(args.ml_frames), "--fixed-dt", f"{args.ml_dt:.6f}", "--no-plot", "-q",
         "--out", d] + settings)
    frames = read_csv(os.path.join(d, "frames.csv"))
    steady = frames[1:] or frames
    return {"gi_ms": gi_ms(frames), "frame_ms": median([num(r, "frame_ms") for r in steady]),
            "gpu_ms": median([num(r, "gpu_total_ms") for r in steady]),
            "triangles": max(num(r, "triangles") for r in frames)}


def load_ldr(path):
    import numpy as np
    from PIL import Image
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0


def box_blur(a, radius=2):
    import numpy as np
    pad = np.pad(a, radius, mode="edge")
    out = np.zeros_like(a)
    for dy in range(2 * radius + 1):
        for dx in range(2 * radius + 1):
            out += pad[dy:dy + a.shape[0], dx:dx + a.shape[1]]
    return out / (2 * radius + 1) ** 2


def stability(tools, args, pnb, settings, d):
    """Mean frame-to-frame change of the player's images and of the truth's (see the top)."""
    import numpy as np
    player, truth = [], []
    for k in range(args.stability_frames):
        fd = os.path.join(d, f"frame{k}")
        os.makedirs(fd, exist_ok=True)
        run([tools.play, pnb, "--headless", "--camera", "0", "--size", args.ml_size, "--frames", str(k + 1),
             "--fixed-dt", f"{args.ml_dt:.6f}", "--dump", "color,position", "--frame", str(k), "-q",
             "--out", fd] + settings)
        run([tools.reference, pnb, "--frame", fd, "--prefix", f"frame{k}_", "--whole-frame", "--spp",
             str(args.truth_spp), "--time-limit", str(args.frame_time_limit), "--out",
             os.path.join(fd, "truth"), "-q"])
        player.append(load_ldr(os.path.join(fd, f"frame{k}_color.png")))
        truth.append(load_ldr(os.path.join(fd, "truth", "whole_frame.png")))
    figures = {"image_change": [], "truth_change": [], "image_change_static": [], "truth_change_static": []}
    for k in range(1, len(player)):
        dp = np.abs(player[k] - player[k - 1]).mean(axis=2)
        dt = np.abs(truth[k] - truth[k - 1]).mean(axis=2)
        still = box_blur(dt) < 2.0 / 255.0
        figures["image_change"].append(float(dp.mean()))
        figures["truth_change"].append(float(dt.mean()))
        figures["image_change_static"].append(float(dp[still].mean()) if still.any() else NAN)
        figures["truth_change_static"].append(float(dt[still].mean()) if still.any() else NAN)
    out = {k: mean(v) if v else NAN for k, v in figures.items()}
    out["change_ratio"] = ratio(out["image_change"], out["truth_change"])
    return out


def bench_moving_light(tools, args, rows):
    pnb, present = make_container(tools, args.out, "moving-light", ["moving-light"], ["--gi"])
    for technique in args.techniques:
        figures = {}
        for animated in (True, False):
            state = "animated" if animated else "frozen"
            settings = anim_set(tools, animated) + ["--set", f"gi.technique={technique}"]
            base = os.path.join(args.out, "runs", "moving-light", f"{technique}-{state}")
            os.makedirs(os.path.join(base, "judge"), exist_ok=True)
            os.makedirs(os.path.join(base, "cost"), exist_ok=True)
            f = quality(tools, args, pnb, settings, os.path.join(base, "judge"))
            f.update(cost(tools, args, pnb, settings, os.path.join(base, "cost")))
            if animated and technique == args.techniques[0] and args.stability_frames >= 2:
                f.update(stability(tools, args, pnb, settings, os.path.join(base, "stability")))
            figures[animated] = f
        frozen = figures[False]
        for animated in (True, False):
            f = figures[animated]
            row = {"scene": "moving-light", "state": "animated" if animated else "frozen",
                   "technique": technique, "anim_present": present, "size": args.ml_size,
                   "frames": args.ml_frames,
                   "triangles": int(f["triangles"]) if not math.isnan(f["triangles"]) else "",
                   "frame_ratio": ratio(f["frame_ms"], frozen["frame_ms"]),
                   "gpu_ratio": ratio(f["gpu_ms"], frozen["gpu_ms"]),
                   "gi_ratio": ratio(f["gi_rmse_pct"], frozen["gi_rmse_pct"]),
                   "shadow_ratio": ratio(f["misclassified_pct"], frozen["misclassified_pct"]),
                   "flip_ratio": ratio(f["frame_flip_ldr"], frozen["frame_flip_ldr"])}
            row.update({k: v for k, v in f.items() if k in COLUMNS and k not in row})
            rows.append(row)
        a = figures[True]
        print(f"moving-light {technique:6s}: GI RMSE {a['gi_rmse_pct']:.2f} % "
              f"(x{ratio(a['gi_rmse_pct'], frozen['gi_rmse_pct']):.3f} frozen), shadows "
              f"{a['misclassified_pct']:.3f} % (x{ratio(a['misclassified_pct'], frozen['misclassified_pct']):.3f}), "
              f"GI {a['gi_ms']:.2f} ms/frame (frozen {frozen['gi_ms']:.2f})"
              + ("" if present else "  (animation absent)"), flush=True)


# [SECTION] Output ----------------------------------------------------------------------------


def fmt(v, digits=3):
    if v is None or v == "":
        return ""
    if isinstance(v, float):
        return "" if math.isnan(v) else f"{v:.{digits}f}"
    return str(v)


def write_outputs(args, rows, present):
    with open(os.path.join(args.out, "anim.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow({k: fmt(r.get(k, ""), 6) for k in COLUMNS})
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write("# Moving scenes benchmark (scripts/bench-anim)\n\n")
        if not present:
            f.write("**Animation absent**: this build's pnb-play has no anim.enabled setting or pnb-convert "
                    "did not keep the clips/skins, so animated and frozen ran the same (static) frames; "
                    "the ratios below are the noise floor, not the cost of animation.\n\n")
        crowd = [r for r in rows if r["scene"] == "crowd"]
        if crowd:
            f.write(f"## crowd: frame time animated vs frozen in the bind pose ({args.size}, deferred, "
                    f"{args.frames} frames along the overview path, {args.rounds} rounds, medians)\n\n")
            f.write("| walkers | triangles | animated ms | frozen ms | ratio | GPU ratio | deform (skinning) GPU ms |\n"
                    "|---:|---:|---:|---:|---:|---:|---:|\n")
            for n in args.counts:
                a = next(r for r in crowd if r["count"] == n and r["state"] == "animated")
                z = next(r for r in crowd if r["count"] == n and r["state"] == "frozen")
                f.write(f"| {n} | {a['triangles']} | {fmt(a['frame_ms'], 2)} | {fmt(z['frame_ms'], 2)} | "
                        f"{fmt(a['frame_ratio'])} | {fmt(a['gpu_ratio'])} | {fmt(a['deform_ms']) or 'n/a'} |\n")
            f.write("\n")
        light = [r for r in rows if r["scene"] == "moving-light"]
        if light:
            f.write(f"## moving-light: error against the Embree truth over the clip, animated vs frozen "
                    f"({args.ml_size}, camera 0, {args.ml_frames} frames over the 4 s clip, judged every "
                    f"{args.every} frame(s); means over the judged frames)\n\n")
            f.write("| technique | state | GI RMSE % | ratio | GI RMSE / const | shadows misclassified % | ratio | "
                    "frame FLIP | ratio | flicker % | GI flicker % | GI ms/frame |\n"
                    "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n")
            for r in light:
                f.write(f"| {r['technique']} | {r['state']} | {fmt(r.get('gi_rmse_pct'), 2)} | {fmt(r['gi_ratio'])} | "
                        f"{fmt(r.get('gi_rmse_over_constant'))} | {fmt(r.get('misclassified_pct'))} | "
                        f"{fmt(r['shadow_ratio'])} | {fmt(r.get('frame_flip_ldr'))} | {fmt(r['flip_ratio'])} | "
                        f"{fmt(r.get('flicker_pct'))} | {fmt(r.get('gi_flicker_pct'))} | {fmt(r.get('gi_ms'), 2)} |\n")
            stable = [r for r in light if not math.isnan(r.get("image_change", NAN))]
            if stable:
                r = stable[0]
                f.write(f"\n## moving-light: temporal stability ({r['technique']}, animated, "
                        f"{args.stability_frames} consecutive frames, truth {args.truth_spp} paths/pixel)\n\n"
                        "Mean absolute frame-to-frame change of the LDR images (0..1), everywhere and where "
                        "the truth changes by less than 2/255:\n\n"
                        "| player change | truth change | ratio | player change, still regions | truth change, still regions |\n"
                        "|---:|---:|---:|---:|---:|\n"
                        f"| {fmt(r['image_change'], 4)} | {fmt(r['truth_change'], 4)} | {fmt(r['change_ratio'])} | "
                        f"{fmt(r['image_change_static'], 4)} | {fmt(r['truth_change_static'], 4)} |\n")
    print(f"wrote {args.out}/anim.csv and {args.out}/summary.md")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default="build/release")
    p.add_argument("--repo", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
    p.add_argument("--out", default="out/bench/anim")
    p.add_argument("--quick", action="store_true",
                   help="counts 1 10 100, fewer frames, rounds, samples (explicit options still win)")
    p.add_argument("--counts", type=int, nargs="+", help="walker counts (default 1 10 100 1000)")
    p.add_argument("--frames", type=int, help="crowd frames per run (default 20; quick 10)")
    p.add_argument("--rounds", type=int, help="crowd rounds of animated+frozen (default 3; quick 2)")
    p.add_argument("--size", default="480x270", help="crowd render size")
    p.add_argument("--ml-size", help="moving-light render size (default 320x180; quick 240x135)")
    p.add_argument("--ml-frames", type=int, help="moving-light frames over its 4 s clip (default 8; quick 4)")
    p.add_argument("--every", type=int, default=2, help="judge every N-th moving-light frame (default 2)")
    p.add_argument("--gi-samples", type=int, help="GI truth rays per pixel (default 64; quick 32)")
    p.add_argument("--frame-samples", type=int, help="whole-frame truth paths per pixel (default 256; quick 64)")
    p.add_argument("--frame-time-limit", type=float, help="seconds per whole-frame truth (default 60; quick 20)")
    p.add_argument("--stability-frames", type=int, help="consecutive frames for temporal stability (default 6; quick 3; 0: skip)")
    p.add_argument("--truth-spp", type=int, help="paths per pixel of the stability truth (default 64; quick 32)")
    p.add_argument("--techniques", help="comma-separated GI techniques (default lpv,probes; quick lpv)")
    p.add_argument("--skip-crowd", action="store_true")
    p.add_argument("--skip-moving-light", action="store_true")
    args = p.parse_args()

    def pick(value, full, quick):
        return value if value is not None else (quick if args.quick else full)

    args.counts = pick(args.counts, [1, 10, 100, 1000], [1, 10, 100])
    if any(not 1 <= n <= 1000 for n in args.counts):
        sys.exit("bench-anim: walker counts are 1..1000")
    args.frames = pick(args.frames, 20, 10)
    args.rounds = pick(args.rounds, 3, 2)
    args.ml_size = pick(args.ml_size, "320x180", "240x135")
    args.ml_frames = pick(args.ml_frames, 8, 4)
    args.ml_dt = 4.0 / args.ml_frames  # the moving-light clip is 4 s
    args.gi_samples = pick(args.gi_samples, 64, 32)
    args.frame_samples = pick(args.frame_samples, 256, 64)
    args.frame_time_limit = pick(args.frame_time_limit, 60, 20)
    args.stability_frames = pick(args.stability_frames, 6, 3)
    args.truth_spp = pick(args.truth_spp, 64, 32)
    args.techniques = pick(args.techniques, "lpv,probes", "lpv").split(",")
    args.repo = os.path.abspath(args.repo)
    os.makedirs(args.out, exist_ok=True)

    tools = Tools(args.build)
    if not tools.anim_setting:
        print("bench-anim: pnb-play has no anim.enabled setting: animation absent, animated and frozen "
              "run the same frames", flush=True)
    rows = []
    if not args.skip_crowd:
        bench_crowd(tools, args, rows)
    if not args.skip_moving_light:
        bench_moving_light(tools, args, rows)
    if not rows:
        sys.exit("bench-anim: nothing to run")
    write_outputs(args, rows, all(r["anim_present"] for r in rows))


if __name__ == "__main__":
    main()
