#!/usr/bin/env bash
# The ground-truth loop as a user runs it: pnb-play dumps a frame of a procedural scene,
# pnb-reference traces it with Embree and scores the player's shadows; and pnb-play
# --shadow-metrics does the same in-process along the camera path. Both must agree that the
# default shadows are close to the truth, and a bad input must be named.
# Usage: play_reference_test.sh PNB_PLAY PNB_REFERENCE SCENE.pnb
set -euo pipefail
play=$1
reference=$2
scene=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
py=/usr/bin/python3

"$play" "$scene" --headless --camera 0 --size 256x144 --set shadows.resolution=1024 \
    --dump position,normal,shadow --frame 0 --out "$tmp/dump" -q
"$reference" "$scene" --frame "$tmp/dump" --prefix frame0_ --out "$tmp/ref" -q
for f in visibility.exr visibility.png shadow_diff.png metrics.json; do
    [ -s "$tmp/ref/$f" ] || fail "pnb-reference did not write $f"
done
$py - "$tmp/ref/metrics.json" <<'PY' || fail "single-frame error out of bounds"
import json, sys
m = json.load(open(sys.argv[1]))
s = m["shadow"]
assert s["pixels"] > 10000, s
assert 0 <= s["misclassified_percent"] < 2.0, s
assert 5 < m["reference"]["lit_percent"] < 100, m["reference"]
PY

"$play" "$scene" --headless --bench --frames 4 --fixed-dt --size 192x108 --no-plot -q \
    --set shadows.resolution=512 --shadow-metrics 2 --out "$tmp/bench"
[ -s "$tmp/bench/quality.csv" ] || fail "no quality.csv"
$py - "$tmp/bench/summary.json" <<'PY' || fail "path error out of bounds"
import json, sys
q = json.load(open(sys.argv[1]))["quality"]
for k in ["misclassified_pct", "mean_abs_error", "flicker_pct", "spurious_flicker_pct", "texel_ratio_median_c0"]:
    assert k in q, (k, sorted(q))
assert q["misclassified_pct"]["frames"] == 2, q["misclassified_pct"]
assert q["misclassified_pct"]["max"] < 3.0, q["misclassified_pct"]
PY

set +e
"$reference" "$scene" --frame "$tmp/dump" --prefix nothing_ --out "$tmp/bad" >"$tmp/out" 2>&1
code=$?
set -e
[ "$code" -eq 2 ] || fail "missing input exited $code, expected 2"
grep -q "nothing_frame.json" "$tmp/out" || { cat "$tmp/out"; fail "the missing file is not named"; }
"$play" "$scene" --headless --shadow-metrics 2 -q >"$tmp/out" 2>&1 && fail "--shadow-metrics without --bench accepted"
echo "ok"
