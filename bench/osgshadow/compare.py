#!/usr/bin/env python3
"""Our shadows against osgShadow's on the same scene, camera and sun (scripts/bench-osgshadow-compare).

Cost: pnb-play frame time (GPU timer queries; on llvmpipe the GPU is the CPU) with shadows off and
with each of our configurations, against osgshadow's frame time from out/osgshadow/summary.json
(the stock binary timed by bench/osgshadow/frame_clock.c, glFinish per frame). Both at 1280x720
on this machine; osgshadow's run was a different process at a different time, so its absolute
times are compared alongside the ratio each tool has to its own no-shadow frame.

Error: both against the same Embree truth. pnb-play dumps the street camera's positions, normals
and shadow factors at 1280x720; pnb-reference traces them. osgShadow's shadow mask comes from its
screenshots: a pixel is shadowed where the shadowed image is darker than osgshadow's no-shadow
image of the same view (luminance ratio < 0.85; OSG's PSSM keeps 70 % in shadow). Pixels count
where our dump says a surface faces the sun (pnb-reference's shadow_diff.png: not magenta, not
background) and where the osg no-shadow image is not background.
"""
import argparse
import json
import os
import subprocess

from PIL import Image


def lum(p):
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]


def osg_error(osg_dir, ref_dir, tech):
    none = Image.open(os.path.join(osg_dir, "none.png")).convert("RGB")
    shad = Image.open(os.path.join(osg_dir, tech + ".png")).convert("RGB")
    truth = Image.open(os.path.join(ref_dir, "visibility.png")).convert("RGB")
    diff = Image.open(os.path.join(ref_dir, "shadow_diff.png")).convert("RGB")
    assert none.size == truth.size, (none.size, truth.size)
    bg = none.getpixel((0, 0))
    n = wrong = false_lit = false_shadow = 0
    for y in range(none.size[1]):
        for x in range(none.size[0]):
            d = diff.getpixel((x, y))
            if d in ((0, 0, 96), (230, 0, 230)):
                continue  # no geometry / facing away from the sun in our dump
            a = none.getpixel((x, y))
            if a == bg or lum(a) < 8:
                continue
            shadowed = lum(shad.getpixel((x, y))) < 0.85 * lum(a)
            lit = truth.getpixel((x, y)) == (255, 255, 255)
            n += 1
            if shadowed == lit:
                wrong += 1
                if shadowed:
                    false_shadow += 1
                else:
                    false_lit += 1
    return {"pixels": n, "misclassified_pct": 100.0 * wrong / max(n, 1),
            "false_lit_pct": 100.0 * false_lit / max(n, 1), "false_shadow_pct": 100.0 * false_shadow / max(n, 1)}


def run_ours(args, label, sets, out):
    d = os.path.join(out, label)
    base = [args.player, args.scene, "--headless", "--camera", "0", "--size", "1280x720", "-q"]
    cmd = base + ["--bench", "--frames", str(args.frames), "--fixed-dt", "--no-plot", "--out", d + "/bench"]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True)
    with open(os.path.join(d, "bench", "summary.json")) as f:
        ms = json.load(f)["gpu_ms"]["total"]["median_ms"]
    result = {"settings": sets, "frame_ms": ms}
    if "shadows.technique=off" not in sets:
        dump = base + ["--dump", "position,normal,shadow", "--out", d + "/dump"]
        for s in sets:
            dump += ["--set", s]
        subprocess.run(dump, check=True)
        subprocess.run([args.reference, args.scene, "--frame", d + "/dump", "--prefix", "frame0_",
                        "--out", d + "/ref", "-q"], check=True)
        with open(os.path.join(d, "ref", "metrics.json")) as f:
            m = json.load(f)["shadow"]
        result.update(misclassified_pct=m["misclassified_percent"], false_lit_pct=m["false_lit_percent"],
                      false_shadow_pct=m["false_shadow_percent"], mean_abs_error=m["mean_abs_error"])
    return result


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--player", required=True)
    ap.add_argument("--reference", required=True)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--osg", default="out/osgshadow")
    ap.add_argument("--out", default="out/bench/osgshadow-compare")
    ap.add_argument("--frames", type=int, default=40)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    configs = {
        "off": ["shadows.technique=off"],
        "sdsm-4x2048": ["shadows.technique=sdsm", "shadows.cascades=4", "shadows.resolution=2048"],
        "sdsm-4x2048-hardware": ["shadows.technique=sdsm", "shadows.cascades=4", "shadows.resolution=2048",
                                 "shadows.filter=hardware"],
        "pssm-4x2048": ["shadows.technique=pssm", "shadows.cascades=4", "shadows.resolution=2048"],
        "pssm-2x2048": ["shadows.technique=pssm", "shadows.cascades=2", "shadows.resolution=2048"],
    }
    rounds = {k: [] for k in configs}
    results = {}
    for r in range(args.rounds):
        for label, sets in configs.items():
            res = run_ours(args, label, sets, args.out)
            rounds[label].append(res["frame_ms"])
            results[label] = res
    for label in configs:
        v = sorted(rounds[label])
        results[label]["frame_ms"] = v[len(v) // 2]
        results[label]["frame_ms_rounds"] = rounds[label]
    off = results["off"]["frame_ms"]
    for label in configs:
        results[label]["ratio_to_off"] = results[label]["frame_ms"] / off
    with open(os.path.join(args.osg, "summary.json")) as f:
        osg = json.load(f)
    ref_dir = os.path.join(args.out, "sdsm-4x2048", "ref")
    peer = {}
    for tech in ["vdsm", "pssm", "lispsm"]:
        o = osg["results"][tech]
        peer[tech] = dict(label=o["label"], frame_ms=o["median_ms"], ratio_to_none=o["ratio_to_none"],
                          **osg_error(os.path.join(args.osg, "screenshots"), ref_dir, tech))
    peer["none"] = {"frame_ms": osg["results"]["none"]["median_ms"]}
    summary = {"ours": results, "osgshadow": peer,
               "sdsm_vs_vdsm_frame_time": results["sdsm-4x2048"]["frame_ms"] / peer["vdsm"]["frame_ms"]}
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    lines = ["| | frame ms | × own no-shadow | misclassified % | false lit % | false shadow % |", "|---|--:|--:|--:|--:|--:|"]
    for label, r in results.items():
        lines.append("| ours %s | %.1f | %.2f | %s | %s | %s |" % (
            label, r["frame_ms"], r["ratio_to_off"],
            *(("%.3f" % r[k]) if k in r else "–" for k in ["misclassified_pct", "false_lit_pct", "false_shadow_pct"])))
    lines.append("| osgShadow none | %.1f | 1.00 | – | – | – |" % peer["none"]["frame_ms"])
    for tech in ["vdsm", "pssm", "lispsm"]:
        p = peer[tech]
        lines.append("| osgShadow %s | %.1f | %.2f | %.3f | %.3f | %.3f |" % (
            p["label"], p["frame_ms"], p["ratio_to_none"], p["misclassified_pct"], p["false_lit_pct"], p["false_shadow_pct"]))
    with open(os.path.join(args.out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
