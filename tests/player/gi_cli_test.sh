#!/usr/bin/env bash
# GI end to end as a user runs it: convert with --gi, play, dump the indirect light, measure it
# against the ray-traced truth with pnb-reference and with pnb-play --gi-metrics.
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
head -1 "$tmp/bench/quality.csv" | grep -q "gi_rmse_pct" || fail "quality.csv has no gi_rmse_pct"
awk -F, 'NR == 2 { if (!($3 > 0 && $3 < 1e6)) exit 1 }' "$tmp/bench/quality.csv" ||
    fail "gi_rmse_pct is not a finite positive number: $(sed -n 2p "$tmp/bench/quality.csv")"

"$play" "$tmp/gi.pnb" --headless --size 96x54 --dump position,normal,indirect --out "$tmp/frame" -q
"$reference" "$tmp/gi.pnb" --frame "$tmp/frame" --prefix frame0_ --indirect --samples 32 --out "$tmp/ref" -q
for f in indirect_reference.exr indirect_stderr.exr metrics.json; do
    [ -s "$tmp/ref/$f" ] || fail "pnb-reference --indirect did not write $f"
done
grep -q '"energy_ratio"' "$tmp/ref/metrics.json" || fail "metrics.json has no indirect energy_ratio"
echo "gi cli: ok"
