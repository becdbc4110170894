#!/usr/bin/env bash
# GI end to end as a user runs it: convert with --gi, play, dump the indirect light, measure it
# against the ray-traced truth with pnb-reference and with pnb-judge --gi-metrics.
# Usage: gi_cli_test.sh PNB_CONVERT PNB_PLAY PNB_REFERENCE SCENE.glb
set -euo pipefail
convert=$1 play=$2 reference=$3 source=$4
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$convert" "$source" -o "$tmp/plain.pnb" > "$tmp/plain.txt"
grep -q "not written: GI programs" "$tmp/plain.txt" || fail "a conversion without --gi does not say GI was left out"
"$convert" "$source" -o "$tmp/gi.pnb" --gi > "$tmp/gi.txt"
grep -q "deferred_lighting\[GI" "$tmp/gi.txt" || fail "--gi did not build lighting with GI"
grep -q "not written: GI programs" "$tmp/gi.txt" && fail "--gi still lists GI as not written"

# --gi-metrics needs a container with GI.
set +e
"$play" "$tmp/plain.pnb" --headless --bench --frames 2 --out "$tmp/b0" --gi-metrics 1 > "$tmp/out" 2>&1
code=$?
set -e
[ "$code" -eq 1 ] || { cat "$tmp/out"; fail "--gi-metrics on a container without GI exited $code, expected 1"; }

"$play" "$tmp/gi.pnb" --headless --bench --frames 4 --fixed-dt --size 96x54 --out "$tmp/bench" \
    --gi-metrics 2 --gi-samples 16 --no-plot -q
# The header is read into a variable, not piped (`head | grep -q` under pipefail: a SIGPIPE in head
# after grep's match would fail the check spuriously).
header=$(head -1 "$tmp/bench/quality.csv")
grep -q "gi_rmse_pct" <<<"$header" || fail "quality.csv has no gi_rmse_pct"
awk -F, 'NR == 2 { if (!($3 > 0 && $3 < 1e6)) exit 1 }' "$tmp/bench/quality.csv" ||
    fail "gi_rmse_pct is not a finite positive number: $(sed -n 2p "$tmp/bench/quality.csv")"

"$play" "$tmp/gi.pnb" --headless --size 96x54 --dump position,normal,indirect --out "$tmp/frame" -q
"$reference" "$tmp/gi.pnb" --frame "$tmp/frame" --prefix frame0_ --indirect --samples 32 --out "$tmp/ref" -q
for f in indirect_reference.exr indirect_stderr.exr metrics.json; do
    [ -s "$tmp/ref/$f" ] || fail "pnb-reference --indirect did not write $f"
done
grep -q '"energy_ratio"' "$tmp/ref/metrics.json" || fail "metrics.json has no indirect energy_ratio"
# More bounces (issue 40): the converged truth of the same frame is brighter than the one-bounce
# one (the room's walls light each other), says so in metrics.json, and a bad count is refused.
"$reference" "$tmp/gi.pnb" --frame "$tmp/frame" --prefix frame0_ --indirect --samples 32 --indirect-bounces converged \
    --out "$tmp/ref-converged" -q
grep -q '"bounces": "converged"' "$tmp/ref-converged/metrics.json" || fail "metrics.json does not say converged"
/usr/bin/python3 - "$tmp" <<'PY' || fail "the converged truth is not brighter than the one-bounce truth"
import json, sys
one, conv = (json.load(open(sys.argv[1] + d + "/metrics.json"))["indirect"]["reference_mean_luminance"]
             for d in ("/ref", "/ref-converged"))
assert conv > 1.05 * one, (one, conv)
PY
if "$reference" "$tmp/gi.pnb" --frame "$tmp/frame" --prefix frame0_ --indirect --indirect-bounces 0 -q --out "$tmp/ref-bad" 2>/dev/null; then
    fail "--indirect-bounces 0 was accepted"
fi
"$play" "$tmp/gi.pnb" --headless --bench --frames 2 --fixed-dt --size 96x54 --out "$tmp/bench-converged" \
    --gi-metrics 1 --gi-samples 16 --gi-bounces converged --set gi.technique=probes --set gi.bounces=3 --no-plot -q
[ -s "$tmp/bench-converged/quality.csv" ] || fail "--gi-bounces converged wrote no quality.csv"

# Sky visibility indoors (issue 28): the box room's sky light, seen from camera 0 through its open
# side, against the Embree truth. ibl.visibility=probes (the GI probes' rays through the occupancy
# grid) must beat the best constant by a margin and keep the energy; the height map takes the
# roof to hide the open side (measured 0.08 of the energy, 1.9 x the constant's error).
"$convert" "$source" -o "$tmp/sky.pnb" --gi --sky --environment-size 64 --specular-size 16 -q
for v in probes height; do
    "$play" "$tmp/sky.pnb" --headless --bench --fixed-dt --no-plot -q --camera 0 --frames 2 --size 160x90 \
        --sky-metrics 1 --sky-samples 64 --set gi.enabled=true --set gi.technique=probes \
        --set ibl.visibility=$v --out "$tmp/sky-$v"
done
/usr/bin/python3 - "$tmp" <<'PY' || fail "probe sky visibility is not closer to the truth than a constant"
import csv, sys
row = lambda v: {k: float(x) for k, x in list(csv.DictReader(open(sys.argv[1] + "/sky-%s/quality.csv" % v)))[0].items()}
p, h = row("probes"), row("height")
print("sky, box room: probes energy %.3f, rmse/constant %.3f, correlation %.3f; height %.3f, %.3f"
      % (p["sky_energy_ratio"], p["sky_rmse_over_constant"], p["sky_correlation"], h["sky_energy_ratio"],
         h["sky_rmse_over_constant"]))
# Measured at 160x90, 64 rays, the open directions weighted by the sky's radiance (issue 40):
# probes 0.906, 0.456, 0.905; height 0.081, 1.939 (counted as open fractions before: probes
# 0.843, 0.496, 0.921, 16^3 probes 0.866, 0.495, 0.911; height 0.058, 1.878).
assert 0.75 <= p["sky_energy_ratio"] <= 1.33, p
assert p["sky_rmse_over_constant"] < 0.75 and p["sky_correlation"] > 0.8, p
assert h["sky_rmse_over_constant"] > 2 * p["sky_rmse_over_constant"], h
PY
echo "gi cli: ok"
