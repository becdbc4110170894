#!/usr/bin/env python3
"""Sky and image-based lighting: what each term costs and how wrong each sky-visibility choice is.

Per scene (converted with --sky): fly the scene's camera path with pnb-play --bench in each
configuration, interleaved round by round so that drift on a noisy machine hits all alike, and
read the GPU time of the lighting pass (and the background pass) per frame; the error of the sky
irradiance the lighting applied against the Embree sky-light truth (pnb-play --sky-metrics:
energy ratio, relative RMSE with and without the truth's own noise, that RMSE over the best
constant's and the correlation).

Costs are ratios to the lighting pass with ibl.enabled=false measured in the same rounds (the
volume term: compare with "GI, sky without visibility", which has GI's look-up too).
Writes OUT/<scene>/{ibl.csv, ibl.md, runs/}.
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys

CONFIGS = [
    # name, settings (the scene is converted with --sky --gi; GI is off unless said)
    ("off", ["ibl.enabled=false", "gi.enabled=false"]),
    ("diffuse", ["ibl.specular=false", "ibl.visibility=none", "gi.enabled=false"]),
    ("diffuse+specular", ["ibl.visibility=none", "gi.enabled=false"]),
    ("+screen visibility", ["ibl.visibility=screen", "gi.enabled=false"]),
    ("+height visibility", ["ibl.visibility=height", "gi.enabled=false"]),
    # The LPV's geometry as the visibility term: against the same frame with GI and no term.
    ("GI, sky without visibility", ["ibl.visibility=none", "gi.enabled=true"]),
    ("GI, sky + volume visibility", ["ibl.visibility=volume", "gi.enabled=true"]),
    # The probes' own visibility: against the same frame with GI probes and no term.
    ("GI probes, sky without visibility", ["ibl.visibility=none", "gi.enabled=true", "gi.technique=probes"]),
    ("GI probes, sky + probes visibility", ["ibl.visibility=probes", "gi.enabled=true", "gi.technique=probes"]),
]


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        sys.exit("bench-ibl: failed: %s\n%s" % (" ".join(cmd), r.stdout[-2000:]))
    return r.stdout


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--player", required=True)
    ap.add_argument("--converter", required=True)
    ap.add_argument("--scene-dir", required=True)
    ap.add_argument("--paths", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--size", default="640x360")
    ap.add_argument("--frames", type=int, default=40)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--every", type=int, default=20, help="sky metrics every N frames")
    ap.add_argument("--samples", type=int, default=128, help="truth rays per pixel")
    ap.add_argument("scenes", nargs="+")
    a = ap.parse_args()
    for scene in a.scenes:
        out = os.path.join(a.out, scene)
        runs = os.path.join(out, "runs")
        os.makedirs(runs, exist_ok=True)
        pnb = os.path.join(out, scene + "-sky.pnb")
        cmd = [a.converter, os.path.join(a.scene_dir, scene + ".glb"), "-o", pnb, "--sky", "--gi", "-q"]
        path = os.path.join(a.paths, scene + ".json")
        if os.path.exists(path):
            cmd += ["--path", path]
        run(cmd)
        lighting = {name: [] for name, _ in CONFIGS}
        background = {name: [] for name, _ in CONFIGS}
        quality = {}
        for rnd in range(a.rounds):
            order = CONFIGS if rnd % 2 == 0 else list(reversed(CONFIGS))
            for name, settings in order:
                d = os.path.join(runs, "%s-r%d" % (name.replace("+", "").replace(" ", "_"), rnd))
                cmd = [a.player, pnb, "--headless", "--bench", "--fixed-dt", "--frames", str(a.frames),
                       "--size", a.size, "--out", d, "--no-plot", "-q"]
                for s in settings:
                    cmd += ["--set", s]
                # The error once per configuration (it does not change between rounds).
                if rnd == 0 and name != "off":
                    cmd += ["--sky-metrics", str(a.every), "--sky-samples", str(a.samples)]
                run(cmd)
                j = json.load(open(os.path.join(d, "summary.json")))
                g = j["gpu_ms"]
                lighting[name].append(g["lighting"]["median_ms"])
                if "background" in g:
                    background[name].append(g["background"]["median_ms"])
                if rnd == 0 and name != "off":
                    q = j["quality"]
                    quality[name] = {k: q[k]["mean"] for k in q if k.startswith("sky_")}
        base = statistics.median(lighting["off"])
        rows = []
        for name, settings in CONFIGS:
            m = statistics.median(lighting[name])
            q = quality.get(name, {})
            rows.append({
                "configuration": name,
                "settings": " ".join(settings),
                "lighting_ms": round(m, 3),
                "lighting_ratio": round(m / base, 3),
                "background_ms": round(statistics.median(background[name]), 3) if background[name] else "",
                "sky_energy_ratio": round(q["sky_energy_ratio"], 3) if q else "",
                "sky_rmse_pct": round(q["sky_rmse_pct"], 1) if q else "",
                "sky_corrected_rmse_pct": round(q["sky_corrected_rmse_pct"], 1) if q else "",
                "sky_reference_noise_pct": round(q["sky_reference_noise_pct"], 1) if q else "",
                # The yardstick: the error against the best constant's (the truth's mean).
                "sky_rmse_over_constant": round(q["sky_rmse_over_constant"], 3) if q else "",
                "sky_correlation": round(q["sky_correlation"], 3) if q else "",
                "sky_flicker_pct": round(q["sky_flicker_pct"], 2) if q and "sky_flicker_pct" in q else "",
            })
        with open(os.path.join(out, "ibl.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(rows)
        cols = list(rows[0].keys())
        md = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
        for r in rows:
            md.append("| " + " | ".join(str(r[c]) for c in cols) + " |")
        text = "%s: %s, %d frames x %d rounds, lighting without IBL %.2f ms (median)\n\n%s\n" % (
            scene, a.size, a.frames, a.rounds, base, "\n".join(md))
        open(os.path.join(out, "ibl.md"), "w").write(text)
        print(text)


if __name__ == "__main__":
    main()
