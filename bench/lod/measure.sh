#!/usr/bin/env bash
# Level-of-detail selection: triangles drawn and image error against full detail (lod.force=0)
# along a path, per lod.threshold_px (docs/PLAYER.md "Level of detail"). Usage:
#   bench/lod/measure.sh BUILD_DIR OUT_DIR [THRESHOLD...]      (default thresholds: 0.25 0.5 1 2)
# Makes load-test (50 rocks, ~1M triangles), converts it with --lods 4, plays bench/lod/
# rocks-walk.json (96 fixed steps, 512x288) once at full detail and once per threshold with
# --lod-metrics 8. A few minutes on 2 cores with llvmpipe. Writes OUT_DIR/figures.json (per
# threshold: triangles and shadow triangles as a share of full detail, mean and worst PSNR):
# the experiment sweep/experiments/lod.toml runs this through pnb-sweep.
set -euo pipefail
build=$(realpath "$1"); out=$(realpath -m "$2"); shift 2
thresholds=("${@:-0.25 0.5 1 2}")
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
"$build/assets_src/pnb-make-scene" load-test "$out/load-test.glb" >/dev/null
"$build/converter/pnb-convert" "$out/load-test.glb" -o "$out/load-test-lod.pnb" --lods 4 | grep "LOD"
play=("$build/player/pnb-play" "$out/load-test-lod.pnb" --headless --bench --path "$here/rocks-walk.json"
      --frames 96 --fixed-dt --no-plot -q)
"${play[@]}" --out "$out/full" --set lod.force=0 >/dev/null
for t in ${thresholds[@]}; do
    "${play[@]}" --out "$out/t$t" --lod-metrics 8 --set lod.threshold_px="$t" >/dev/null
done
python3 - "$out" ${thresholds[@]} <<'PY'
import csv, json, sys
out, ts = sys.argv[1], sys.argv[2:]
full = json.load(open(f"{out}/full/summary.json"))
ft, fs = full["triangles"]["sum"], full["shadow_triangles"]["sum"]
print(f"full detail: {ft} triangles, {fs} shadow triangles along the path")
figures = {}
print("threshold_px  triangles  of full     shadow  of full  PSNR dB mean  min  px>8/255 %  switches")
for t in ts:
    j = json.load(open(f"{out}/t{t}/summary.json"))
    rows = list(csv.DictReader(open(f"{out}/t{t}/quality.csv")))
    psnr = [float(r["lod_psnr_db"]) for r in rows]
    over = [float(r["lod_pixels_over8_pct"]) for r in rows]
    tri, sh = j["triangles"]["sum"], j["shadow_triangles"]["sum"]
    print(f"{t:>12}  {tri:>9}  {100*tri/ft:6.1f}%  {sh:>9}  {100*sh/fs:6.1f}%  "
          f"{sum(psnr)/len(psnr):12.2f}  {min(psnr):5.2f}  {sum(over)/len(over):10.2f}  {j['lod']['switches']:8}")
    figures.update({f"t{t}:triangles_of_full": tri / ft, f"t{t}:shadow_of_full": sh / fs,
                    f"t{t}:psnr_mean_db": sum(psnr) / len(psnr), f"t{t}:psnr_min_db": min(psnr),
                    f"t{t}:pixels_over8_pct": sum(over) / len(over)})
with open(f"{out}/figures.json.tmp", "w") as f:
    json.dump(figures, f, indent=1)
import os
os.replace(f"{out}/figures.json.tmp", f"{out}/figures.json")
PY
