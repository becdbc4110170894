#!/usr/bin/env bash
# The lean player and the judge (docs/ARCHITECTURE.md): pnb-play links no ray tracer and refuses
# the truth metrics naming pnb-judge; pnb-judge links Embree and takes pnb-play's options.
# Usage: lean_player_test.sh PNB_PLAY PNB_JUDGE SCENE.pnb
set -euo pipefail
play=$1 judge=$2 scene=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# Dynamic dependencies: Embree only in the judge (the check is live: it finds it there). Each
# listing goes to a file first: `readelf | grep -q` under pipefail is false when grep matches
# early and readelf dies of SIGPIPE, which would hide pnb-play's hit and flake the judge's.
readelf -d "$play" >"$tmp/play-dynamic" || fail "readelf cannot read $play"
readelf -d "$judge" >"$tmp/judge-dynamic" || fail "readelf cannot read $judge"
if grep -qi 'embree' "$tmp/play-dynamic"; then
    fail "pnb-play links Embree: $(grep -i embree "$tmp/play-dynamic")"
fi
grep -qi 'libembree' "$tmp/judge-dynamic" || fail "pnb-judge does not link Embree: the dependency check is blind"

for metric in --shadow-metrics --gi-metrics --sky-metrics; do
    set +e
    "$play" "$scene" --headless --bench --frames 2 --size 64x36 --out "$tmp/b" "$metric" 1 >"$tmp/out" 2>&1
    code=$?
    set -e
    [ "$code" = 1 ] || fail "pnb-play $metric: exit $code, expected 1 (usage)"
    grep -q -- "$metric compares with the ray-traced truth.*run pnb-judge" "$tmp/out" ||
        fail "pnb-play $metric: the message does not name pnb-judge: $(cat "$tmp/out")"
done

# pnb-judge is pnb-play's command line under its own name ...
"$judge" --help >"$tmp/judge-help"
"$play" --help >"$tmp/play-help"
grep -q '^usage: pnb-judge SCENE.pnb' "$tmp/judge-help" || fail "pnb-judge --help does not name pnb-judge"
grep -q '^usage: pnb-play SCENE.pnb' "$tmp/play-help" || fail "pnb-play --help does not name pnb-play"
set +e
"$judge" "$scene" --headless --shadow-metrics 2 >"$tmp/out" 2>&1
code=$?
set -e
[ "$code" = 1 ] && grep -q '^pnb-judge: --shadow-metrics needs --bench' "$tmp/out" ||
    fail "pnb-judge --shadow-metrics without --bench: exit $code, $(cat "$tmp/out")"
# ... and draws the same frames: one benchmark frame's image is byte-identical from both.
"$play" "$scene" --headless --frames 1 --size 96x54 --screenshot "$tmp/play.png" -q
"$judge" "$scene" --headless --frames 1 --size 96x54 --screenshot "$tmp/judge.png" -q
cmp -s "$tmp/play.png" "$tmp/judge.png" || fail "pnb-play and pnb-judge draw different images"
# and measures: a shadow metric in the summary.
"$judge" "$scene" --headless --bench --frames 2 --size 96x54 --shadow-metrics 1 --out "$tmp/j" -q --no-plot
grep -q 'misclassified_pct' "$tmp/j/summary.json" || fail "pnb-judge --shadow-metrics wrote no misclassified_pct"
echo "ok"
