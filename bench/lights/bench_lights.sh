#!/usr/bin/env bash
# Deferred vs forward frame time against the light count (1, 8, 64 point lights), release build,
# pnb-play headless. The question (seed 003, §5): the layered deferred path shades each covered
# pixel once per layer, forward shades every rasterised fragment; so forward should win or tie
# with few lights (no G-buffer to write and read) and deferred should pull ahead as lights
# multiply. UberRender's baseline on a GTX 1060 at 4K: about equal at 30 lights, deferred +32 %
# FPS at 60 lights (24.6 vs 32.4 ms).
#
# Input (generated here, deterministic): pnb-make-scene light-field --lights N (a 64 m floor,
# 64 boxes, N point lights with finite ranges, plus a dim sun: N + 1 lights are shaded), each N
# converted twice: all materials deferred (the converter's default for opaque) and all forward
# (sidecar {"materials": {"*": {"shading_path": "forward"}}}). The player's default light
# culling applies (lights.culling=auto: clusters from 32 point and spot lights on; docs/PLAYER.md
# "Many lights"; sweep/examples/lights.toml sweeps culling and light count).
#
# Runs: pnb-play --headless --bench --fixed-dt --frames F --size WxH --no-plot along the
# converter's default orbit path (frame k is the same view in every run); rounds of all
# configurations, the deferred and forward runs of one light count back to back (which goes
# first alternates), at 960x540 and 480x270. Each run's summary.json gives the median GPU frame
# time (timer queries, gpu_ms.total) and CPU time. The table gives, per configuration, the
# median over rounds of those per-run medians, and forward / deferred as the median over rounds
# of each round's back-to-back pair (> 1: deferred is faster), with its range: load from other
# tenants comes in bursts of seconds, so the pairs are steadier than the absolute times.
#
# On this machine the "GPU" is Mesa llvmpipe on 2 CPU cores: GPU time is CPU rasterisation, so
# CPU and GPU figures nearly coincide (the CPU waits for the rasteriser whenever a pass samples
# the previous pass's target), and llvmpipe's per-pass timer split is unreliable (it bins draws
# and rasterises at flushes) — use the totals. A real GPU has far more shading throughput per
# memory bandwidth, so absolute times and the break-even light count differ there.
#
# Output: out/bench/lights/results.json (every frame of every run), results.md (the table),
# lights.png (frame time and ratio against lights), frame0-*.png (one frame of the 64-light
# scene from each path, for a visual check; the script prints their largest pixel difference),
# runs/ (each run's summary.json and frames.csv). About 3 minutes on 2 cores (each run also
# pays ~0.6 s of process start, load and first frame, outside the statistics).
# The experiment sweep/experiments/lights-paths.toml runs this (scripts/bench-lights builds and
# runs that through pnb-sweep, which gives --build and --out: the job's directory):
#   bench/lights/bench_lights.sh                            # 16 frames, 7 rounds, both sizes
#   bench/lights/bench_lights.sh --frames 60 --rounds 3 --sizes 960x540
#   --build DIR: the binaries (default build/release); --out DIR: default out/bench/lights
# The machine is shared and noisy: compare ratios within one run, not absolute times across runs.
set -euo pipefail
cd "$(dirname "$0")/../.."

frames=16
rounds=7
sizes="960x540 480x270"
bin=build/release
dir=out/bench/lights
while [ $# -gt 0 ]; do
    case "$1" in
    --frames) frames=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --build) bin=$2; shift 2 ;;
    --out) dir=$2; shift 2 ;;
    *) echo "bench-lights: unknown argument $1 (see the header of $0)" >&2; exit 1 ;;
    esac
done
lights=(1 8 64)
rm -rf "$dir/runs"
mkdir -p "$dir/runs"
export EGL_LOG_LEVEL=fatal
# Debian's matplotlib belongs to /usr/bin/python3 (python3 on PATH may be a pyenv without it).
py=/usr/bin/python3
[ -x "$py" ] || py=python3

echo '{"materials": {"*": {"shading_path": "forward"}}}' >"$dir/forward.pnb.json"
for n in "${lights[@]}"; do
    "$bin/assets_src/pnb-make-scene" light-field "$dir/light-field-$n.glb" --lights "$n" >/dev/null
    "$bin/converter/pnb-convert" "$dir/light-field-$n.glb" -o "$dir/light-field-$n.deferred.pnb" \
        -q --no-sidecar
    "$bin/converter/pnb-convert" "$dir/light-field-$n.glb" -o "$dir/light-field-$n.forward.pnb" \
        -q --sidecar "$dir/forward.pnb.json"
done

# A visual check (untimed): the same frame of the 64-light scene from both paths.
for path in deferred forward; do
    "$bin/player/pnb-play" "$dir/light-field-64.$path.pnb" --headless --size 960x540 \
        --screenshot "$dir/frame0-$path.png" -q
done

run=0
total=$((rounds * ${#lights[@]} * 2 * $(wc -w <<<"$sizes")))
for round in $(seq 1 "$rounds"); do
    for size in $sizes; do
        for n in "${lights[@]}"; do
            # Alternate which path goes first, so drift on the machine spreads over both.
            if [ $(((round + n) % 2)) -eq 0 ]; then order="deferred forward"; else order="forward deferred"; fi
            for path in $order; do
                run=$((run + 1))
                out="$dir/runs/$size-$n-$path-r$round"
                echo "bench-lights: run $run/$total: $n lights, $path, $size, round $round" >&2
                "$bin/player/pnb-play" "$dir/light-field-$n.$path.pnb" --headless --bench --fixed-dt \
                    --frames "$frames" --size "$size" --out "$out" --no-plot -q
            done
        done
    done
done

"$py" - "$dir" "$rounds" "$frames" "$sizes" "${lights[@]}" <<'EOF'
import csv
import json
import os
import statistics
import sys

out_dir, rounds, frames, sizes = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4].split()
lights = [int(x) for x in sys.argv[5:]]
paths = ("deferred", "forward")


def load_run(size, n, path, r):
    d = os.path.join(out_dir, "runs", f"{size}-{n}-{path}-r{r}")
    summary = json.load(open(os.path.join(d, "summary.json")))
    with open(os.path.join(d, "frames.csv")) as f:
        rows = list(csv.DictReader(f))
    num = lambda v: float(v) if v not in ("", None) else None
    return {
        "round": r, "gpu_median_ms": summary["gpu_ms"]["total"]["median_ms"],
        "cpu_median_ms": summary["cpu_ms"]["median_ms"],
        "gpu_passes_median_ms": {k: v["median_ms"] for k, v in summary["gpu_ms"].items()
                                 if k != "total"},
        "frames_gpu_ms": [num(x["gpu_total_ms"]) for x in rows],
        "frames_cpu_ms": [num(x["cpu_ms"]) for x in rows],
        "lights_in_scene": summary["scene"]["lights"], "triangles": summary["scene"]["triangles"],
        "deferred_layers": summary["scene"]["deferred_layers"],
        "has_forward": summary["scene"]["has_forward"],
    }, summary


results, machine, gl = [], None, None
for size in sizes:
    for n in lights:
        row = {"size": size, "point_lights": n}
        for path in paths:
            runs = []
            for r in range(1, rounds + 1):
                data, summary = load_run(size, n, path, r)
                runs.append(data)
                machine, gl = summary["machine"], summary["gl"]
            row[path] = {
                "gpu_ms": statistics.median(x["gpu_median_ms"] for x in runs),
                "cpu_ms": statistics.median(x["cpu_median_ms"] for x in runs),
                "lights_shaded": runs[0]["lights_in_scene"], "runs": runs,
            }
        for kind in ("gpu", "cpu"):
            pairs = [f[kind + "_median_ms"] / d[kind + "_median_ms"]
                     for d, f in zip(row["deferred"]["runs"], row["forward"]["runs"])]
            row[f"forward_over_deferred_{kind}_per_round"] = pairs
            row[f"forward_over_deferred_{kind}"] = statistics.median(pairs)
        results.append(row)

lines = []
p = lines.append
p(f"light-field, {frames} frames along the default orbit (--fixed-dt), {rounds} rounds; "
  f"medians over rounds of each run's median, ms")
p(f"machine: {machine['cpu']}, {machine['cores']} cores; GL: {gl['renderer']}, {gl['version']}")
p("")
p("| size | point lights (+1 sun) | deferred GPU ms | forward GPU ms | forward / deferred "
  "(range) | deferred CPU ms | forward CPU ms | forward / deferred, CPU |")
p("|---|--:|--:|--:|--:|--:|--:|--:|")
for r in results:
    pairs = r["forward_over_deferred_gpu_per_round"]
    p(f"| {r['size']} | {r['point_lights']} | {r['deferred']['gpu_ms']:.1f} | "
      f"{r['forward']['gpu_ms']:.1f} | **{r['forward_over_deferred_gpu']:.2f}** "
      f"({min(pairs):.2f}-{max(pairs):.2f}) | "
      f"{r['deferred']['cpu_ms']:.1f} | {r['forward']['cpu_ms']:.1f} | "
      f"{r['forward_over_deferred_cpu']:.2f} |")
p("")
p("forward / deferred > 1: deferred is faster. Seed 003 baseline (GTX 1060, 4K, UberRender): "
  "deferred 20.1 vs forward 21.1 ms at 30 lights (1.05), 24.6 vs 32.4 ms at 60 lights (1.32), "
  "25.8 vs 34.4 ms at 120 lights (1.33); equal at FHD with 30 lights.")

# Visual check: the largest per-channel difference between the two paths' frames.
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    import matplotlib.pyplot as plt
    a = mpimg.imread(os.path.join(out_dir, "frame0-deferred.png"))
    b = mpimg.imread(os.path.join(out_dir, "frame0-forward.png"))
    diff = abs(a[..., :3] - b[..., :3])
    p(f"64-light frame, deferred vs forward image: max difference {diff.max() * 255:.0f}/255, "
      f"mean {diff.mean() * 255:.2f}/255 (frame0-*.png)")

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for size, style in zip(sizes, ("-", "--", ":")):
        rows = [r for r in results if r["size"] == size]
        xs = [r["point_lights"] for r in rows]
        for path, colour in zip(paths, ("tab:blue", "tab:orange")):
            ax1.plot(xs, [r[path]["gpu_ms"] for r in rows], style, color=colour, marker="o",
                     label=f"{path} {size}")
        mid = [r["forward_over_deferred_gpu"] for r in rows]
        lo = [m - min(r["forward_over_deferred_gpu_per_round"]) for m, r in zip(mid, rows)]
        hi = [max(r["forward_over_deferred_gpu_per_round"]) - m for m, r in zip(mid, rows)]
        ax2.errorbar(xs, mid, yerr=[lo, hi], fmt="o" + style, color="tab:green", capsize=3,
                     label=f"{size} (median, range of rounds)")
    for ax in (ax1, ax2):
        ax.set_xscale("log", base=2)
        ax.set_xticks(lights)
        ax.set_xticklabels([str(n) for n in lights])
        ax.set_xlabel("point lights (+1 sun)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    ax1.set_yscale("log")
    ax1.set_ylabel("GPU frame time, median (ms)")
    ax1.set_title("frame time")
    ax2.axhline(1.0, color="grey", linewidth=0.8)
    ax2.set_ylabel("forward / deferred")
    ax2.set_title("> 1: deferred faster")
    fig.suptitle(f"light-field on {gl['renderer']}", fontsize=9)
    fig.tight_layout()
    png = os.path.join(out_dir, "lights.png")
    fig.savefig(png + ".tmp", dpi=110, format="png")
    os.replace(png + ".tmp", png)
    p(f"plot: {png}")
except ImportError:
    p("plot skipped: matplotlib not available (apt install python3-matplotlib)")

text = "\n".join(lines)
print()
print(text)
open(os.path.join(out_dir, "results.md"), "w").write("# scripts/bench-lights\n\n" + text + "\n")
json.dump({"machine_note": "shared, noisy machine; compare ratios within one run",
           "machine": machine, "gl": gl, "frames": frames, "rounds": rounds,
           "baseline_seed_003": {
               "hardware": "GTX 1060, 3840x2160, UberRender (Java)",
               "frame_ms_deferred_vs_forward": {"30": [20.1, 21.1], "60": [24.6, 32.4],
                                                "120": [25.8, 34.4]}},
           "results": results}, open(os.path.join(out_dir, "results.json"), "w"), indent=1)
EOF
echo "bench-lights: results in $dir/results.json, $dir/results.md, $dir/lights.png"
