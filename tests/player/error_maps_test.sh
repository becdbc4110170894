#!/usr/bin/env bash
# --error-maps end to end (pnb-judge for the truth metrics, pnb-play for --lod-metrics): the heat-maps of the metrics' last measured frame.
#   shadow      error_shadow.png has --size, its red + blue pixels over its classified pixels are
#               that frame's misclassified_pct (and its classified pixels the metric's `pixels`);
#               a bad shadow configuration marks more pixels than a good one; the map overlays the
#               same frame's --screenshot and --dump shadow,position (rows top-down, not flipped)
#   frames      error_maps.json's frame is the last multiple of N below --frames (quality.csv's
#               last row), not the follow-up frame
#   usage       --error-maps without --bench or without a metric is a usage error that says so
#   irradiance  on a container converted with --gi --sky: error_gi.png and error_sky.png have
#               --size and their measured pixels are the metrics' pixel counts
#   lod         on a container converted with --lods: error_lod.png decoded through the ramp gives
#               lod_pixels_over8_pct (pixels off by > 8/255)
# Usage: error_maps_test.sh CASE PNB_PLAY PNB_CONVERT SCENE_DIR
set -euo pipefail
case_=$1 play=$2 convert=$3 scenes=$4
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
py=/usr/bin/python3
bench=(--headless --bench --fixed-dt --no-plot -q)

# Helpers for the Python checks: PNG reading (Pillow), the writer's uncompressed float EXR, the
# quality.csv row of a frame.
cat > "$tmp/maps.py" <<'PY'
import csv, json, struct
import numpy as np
from PIL import Image

OUTSIDE = (40, 40, 40)

def png(path):
    return np.asarray(Image.open(path).convert("RGB")).astype(int)

def quality_row(directory, frame):
    rows = list(csv.DictReader(open(directory + "/quality.csv")))
    match = [r for r in rows if int(r["frame"]) == frame]
    assert len(match) == 1, (frame, [r["frame"] for r in rows])
    return {k: float(v) for k, v in match[0].items() if v != ""}, rows

def maps_json(directory):
    return json.load(open(directory + "/error_maps.json"))

def shadow_counts(img):
    grey = (img[..., 0] == img[..., 1]) & (img[..., 1] == img[..., 2])
    outside = grey & (img[..., 0] == OUTSIDE[0])
    marked = ~grey
    red = marked & (img[..., 1] == 0) & (img[..., 2] == 0) & (img[..., 0] > 0)
    blue = marked & (img[..., 0] == 0) & (img[..., 2] > img[..., 1])
    assert (red | blue).sum() == marked.sum(), "a marked pixel is neither red nor blue"
    return int((~outside).sum()), int(red.sum()), int(blue.sum())

def read_exr(path):
    """Single-part scanline EXR, NO_COMPRESSION, FLOAT channels (what pnb-play --dump writes)."""
    b = open(path, "rb").read()
    assert b[:4] == bytes([0x76, 0x2F, 0x31, 0x01]), path
    pos, attrs = 8, {}
    while b[pos] != 0:
        end = b.index(0, pos); name = b[pos:end].decode(); pos = end + 1
        end = b.index(0, pos); pos = end + 1
        size = struct.unpack_from("<i", b, pos)[0]; pos += 4
        attrs[name] = b[pos:pos + size]; pos += size
    pos += 1
    names, ch, p = [], attrs["channels"], 0
    while ch[p] != 0:
        end = ch.index(0, p); names.append(ch[p:end].decode()); p = end + 1 + 16
    xmin, ymin, xmax, ymax = struct.unpack("<4i", attrs["dataWindow"])
    w, h = xmax - xmin + 1, ymax - ymin + 1
    img = np.zeros((h, w, len(names)), np.float32)
    for off in struct.unpack_from("<%dQ" % h, b, pos):
        y = struct.unpack_from("<i", b, off)[0]
        img[y - ymin] = np.frombuffer(b, "<f4", w * len(names), off + 8).reshape(len(names), w).T
    return dict(zip(names, np.moveaxis(img, 2, 0)))
PY
export PYTHONPATH="$tmp"

case "$case_" in
shadow)
    scene="$scenes/flat-city.pnb"
    # Good: the default shadows; bad: one 256² map. 10 frames, every 4th measured: 0, 4, 8.
    "$play" "$scene" "${bench[@]}" --frames 10 --size 192x108 --shadow-metrics 4 --error-maps \
        --screenshot "$tmp/good/shot.png" --frame 8 --dump shadow,position --out "$tmp/good"
    "$play" "$scene" "${bench[@]}" --frames 10 --size 192x108 --shadow-metrics 4 --error-maps \
        --set shadows.resolution=256 --set shadows.cascades=1 --out "$tmp/bad"
    [ -s "$tmp/good/error_shadow.png" ] || fail "no error_shadow.png"
    $py - "$tmp/good" "$tmp/bad" <<'PY' || fail "error_shadow.png does not match the metric"
import sys
import numpy as np
from maps import *
marked = {}
for d in sys.argv[1:]:
    j = maps_json(d)
    assert j["frame"] == 8 and [m["file"] for m in j["maps"]] == ["error_shadow.png"], j
    assert j["maps"][0]["frame"] == 8 and len(j["maps"][0]["legend"]) >= 5, j["maps"][0]
    row, rows = quality_row(d, 8)
    assert int(rows[-1]["frame"]) == 8, "the map's frame is not quality.csv's last measured frame"
    img = png(d + "/error_shadow.png")
    assert img.shape == (108, 192, 3), img.shape
    classified, red, blue = shadow_counts(img)
    pct = 100.0 * (red + blue) / classified
    print(d, "classified", classified, "red", red, "blue", blue, "pct %.6f" % pct,
          "csv %g (lit %g, shadow %g)" % (row["misclassified_pct"], row["false_lit_pct"], row["false_shadow_pct"]))
    assert classified == int(row["pixels"]), (classified, row["pixels"])
    # quality.csv holds 6 significant digits.
    for got, want in [(pct, row["misclassified_pct"]), (100.0 * red / classified, row["false_lit_pct"]),
                      (100.0 * blue / classified, row["false_shadow_pct"])]:
        assert abs(got - want) <= 1e-5 * max(1.0, want), (got, want)
    marked[d] = red + blue
good, bad = sys.argv[1:]
assert marked[bad] > 2 * marked[good] and marked[bad] > 50, marked

# Overlay with the same frame's captures: the pixels --dump leaves out (no position, or a shadow
# value < 0: facing away) are exactly the map's dark grey ones; the screenshot is brighter where the map says lit in both than where
# it says shadowed in both. Upside down, neither holds.
img = png(good + "/error_shadow.png")
vis = read_exr(good + "/frame8_shadow.exr")["R"]
left_out = ~np.isfinite(read_exr(good + "/frame8_position.exr")["R"]) | ~(vis >= 0)
shot = png(good + "/shot.png").mean(axis=2)
assert vis.shape == img.shape[:2] and shot.shape == img.shape[:2], (vis.shape, shot.shape)
def agreement(m):
    outside = (m == OUTSIDE).all(axis=2)
    return float((outside == left_out).mean())
def contrast(m):
    lit, dark = (m == 210).all(axis=2), (m == 150).all(axis=2)
    return shot[lit].mean() / max(shot[dark].mean(), 1e-3)
print("overlay: mask agreement %.5f (flipped %.5f), lit/shadow brightness %.2f (flipped %.2f)"
      % (agreement(img), agreement(img[::-1]), contrast(img), contrast(img[::-1])))
assert agreement(img) == 1.0 and agreement(img[::-1]) < 0.95
assert contrast(img) > 3.0 and contrast(img[::-1]) < 1.5
PY
    ;;
frames)
    # The last measured frame for other --frames: 9 -> 8, 8 -> 4 (frames 0..7), 3 -> 0.
    scene="$scenes/street-canyon.pnb"
    for pair in "9 8" "8 4" "3 0"; do
        set -- $pair
        "$play" "$scene" "${bench[@]}" --frames "$1" --size 128x72 --shadow-metrics 4 --error-maps --out "$tmp/f$1"
        $py - "$tmp/f$1" "$2" <<'PY' || fail "--frames $1: the maps are not of frame $2"
import sys
from maps import *
d, want = sys.argv[1], int(sys.argv[2])
j = maps_json(d)
assert j["frame"] == want and j["maps"][0]["frame"] == want, j["frame"]
row, rows = quality_row(d, want)
assert int(rows[-1]["frame"]) == want
classified, red, blue = shadow_counts(png(d + "/error_shadow.png"))
assert classified == int(row["pixels"]), (classified, row)
PY
    done
    ;;
usage)
    scene="$scenes/flat-city.pnb"
    for extra in "--bench --out $tmp/u1" "--shadow-metrics 2" "--size 64x64"; do
        set +e
        # shellcheck disable=SC2086
        "$play" "$scene" --headless --frames 2 --error-maps $extra > "$tmp/out" 2>&1
        code=$?
        set -e
        [ "$code" -eq 1 ] || { cat "$tmp/out"; fail "--error-maps $extra exited $code, expected 1 (usage)"; }
        grep -q -- "--error-maps needs --bench and at least one of --shadow-metrics" "$tmp/out" ||
            { cat "$tmp/out"; fail "--error-maps $extra: the message does not say what is missing"; }
    done
    [ ! -e "$tmp/u1/error_maps.json" ] || fail "a usage error still wrote maps"
    "$play" --help > "$tmp/help"
    grep -q -- "--error-maps" "$tmp/help" || fail "--help does not list --error-maps"
    ;;
irradiance)
    "$convert" "$scenes/street-canyon.glb" -o "$tmp/s.pnb" --sky --gi --environment-size 64 --specular-size 16 -q \
        --path "$(dirname "$0")/../../assets_src/paths/street-canyon.json"
    "$play" "$tmp/s.pnb" "${bench[@]}" --frames 6 --size 128x72 --gi-metrics 5 --sky-metrics 5 \
        --gi-samples 8 --sky-samples 8 --error-maps --out "$tmp/irr"
    $py - "$tmp/irr" <<'PY' || fail "error_gi/sky.png do not match the metrics"
import sys
import numpy as np
from maps import *
d = sys.argv[1]
j = maps_json(d)
files = [m["file"] for m in j["maps"]]
assert j["frame"] == 5 and files == ["error_gi.png", "compare_gi.png", "error_sky.png", "compare_sky.png"], j
row, rows = quality_row(d, 5)
for metric in ("gi", "sky"):
    # The scorecard's headline is the noise-removed RMSE over the best constant's, same pixels.
    ratio = row[metric + "_corrected_rmse_pct"] / row[metric + "_best_constant_rmse_pct"]
    assert abs(row[metric + "_rmse_over_constant"] - ratio) <= 1e-4 * ratio, (metric, row)
    assert -1 <= row[metric + "_correlation"] <= 1 and row[metric + "_zero_rmse_pct"] > 0, row
    # The side-by-side: player | truth | difference, each panel the frame's size, unmeasured
    # pixels the same in all three and in the error map.
    side = png(d + "/compare_%s.png" % metric)
    assert side.shape == (72, 3 * 128, 3), side.shape
    outside = [(side[:, k * 128:(k + 1) * 128] == OUTSIDE).all(axis=2) for k in range(3)]
    heat = (png(d + "/error_%s.png" % metric) == OUTSIDE).all(axis=2)
    assert all((o == heat).all() for o in outside), metric
    # The player's panel differs from the truth's: they are two images, not one drawn twice.
    assert (side[:, :128] != side[:, 128:256]).any(), metric
for m in [m for m in j["maps"] if m["file"].startswith("error_")]:
    img = png(d + "/" + m["file"])
    assert img.shape == (72, 128, 3), (m["file"], img.shape)
    assert m["frame"] == 5 and m["clamp"] == 1.0 and m["legend"], m
    measured = int((~(img == OUTSIDE).all(axis=2)).sum())
    print(m["file"], "measured", measured, "csv", row[m["metric"] + "_pixels"], m["stats"])
    assert measured == int(row[m["metric"] + "_pixels"]) and measured > 1000, (measured, row)
    assert m["stats"]["measured_pixels"] == measured
    # Every measured pixel is a colour of the ramp (never the dark grey, never another grey).
    grey = (img[..., 0] == img[..., 1]) & (img[..., 1] == img[..., 2])
    assert (grey == (img == OUTSIDE).all(axis=2)).all()
PY
    ;;
lod)
    # Terrain with levels of detail: the selected levels differ visibly from full detail.
    "$convert" "$scenes/terrain.glb" -o "$tmp/t.pnb" --lods 3 -q
    "$play" "$tmp/t.pnb" "${bench[@]}" --frames 6 --size 128x72 --lod-metrics 5 --set lod.threshold_px=8 \
        --error-maps --out "$tmp/lod"
    $py - "$tmp/lod" <<'PY' || fail "error_lod.png does not match lod_pixels_over8_pct"
import math, sys
import numpy as np
from maps import *
d = sys.argv[1]
j = maps_json(d)
assert j["frame"] == 5 and [m["file"] for m in j["maps"]] == ["error_lod.png"], j
m = j["maps"][0]
assert abs(m["clamp"] - 32 / 255) < 1e-12, m
row, rows = quality_row(d, 5)
img = png(d + "/error_lod.png")
assert img.shape == (72, 128, 3), img.shape
# Decode the map: the ramp (magma at 9 stops, linear between, rounded) at worst/32, worst 0..32.
stops = [(0, 0, 4), (28, 16, 68), (79, 18, 123), (129, 37, 129), (181, 54, 122), (229, 80, 100),
         (251, 135, 97), (254, 194, 135), (252, 253, 191)]
def ramp(t):
    if t >= 1: return stops[8]
    s = t * 8; i = min(int(s), 7); f = s - i
    return tuple(int(math.floor(a + f * (b - a) + 0.5)) for a, b in zip(stops[i], stops[i + 1]))
lut = {ramp(k / 32): k for k in range(33)}
assert len(lut) == 33, "the ramp does not tell 0..32 apart"
worst = np.vectorize(lambda r, g, b: lut.get((r, g, b), -1))(img[..., 0], img[..., 1], img[..., 2])
assert (worst >= 0).all(), "a pixel of error_lod.png is not a ramp colour"
over8 = 100.0 * (worst > 8).sum() / worst.size
print("over8 from the map %.5f, csv %g, clamped %d" % (over8, row["lod_pixels_over8_pct"], (worst == 32).sum()))
assert row["lod_pixels_over8_pct"] > 1.0, row
assert abs(over8 - row["lod_pixels_over8_pct"]) <= 1e-5 * row["lod_pixels_over8_pct"], (over8, row)
assert abs(m["stats"]["pixels_over8_pct"] - over8) < 1e-9
PY
    ;;
*) fail "unknown case $case_" ;;
esac
echo "error maps ($case_): ok"
