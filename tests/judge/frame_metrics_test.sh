#!/usr/bin/env bash
# pnb-judge --frame-metrics end to end on box-room (96x54, the truth at its default noise target):
#   columns   quality.csv has every frame_* column; FLIP in (0, 1); the truth's own noise is under a
#             tenth of the relative MSE it feeds (issue 40); --error-maps writes error_frame.png
#             (--size) and compare_frame.png (3 x --size, the truth's panel not black)
#   cache     a second run reads the cached truth (frame_truth_cached 1, the same figures); a cache
#             file with one byte changed fails its checksum and is traced again (the same figures:
#             the truth is deterministic), never read
#   worse     the sun turned 60 degrees from where the truth has it is judged worse, in FLIP and relMSE
#             (shadows off is not: without GI, the shadows the truth fills with bounced light are
#             darker in the player than no shadow at all)
#   usage     --frame-truth-cache without --frame-metrics is a usage error
# Usage: frame_metrics_test.sh PNB_JUDGE SCENE.pnb
set -euo pipefail
judge=$1 scene=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
run() { # run OUT [options...]
    local out=$1; shift
    "$judge" "$scene" --headless --bench --fixed-dt --no-plot -q --frames 2 --size 96x54 --out "$out" \
        --frame-metrics 2 "$@"
}
col() { # col DIR COLUMN: frame 0's value
    /usr/bin/python3 -c 'import csv,sys; print(next(csv.DictReader(open(sys.argv[1] + "/quality.csv")))[sys.argv[2]])' "$1" "$2"
}

run "$tmp/a" --frame-truth-cache "$tmp/cache" --error-maps
for c in frame_flip_ldr frame_flip_hdr frame_relmse frame_truth_noise_relmse frame_truth_noise_flip_ldr \
         frame_truth_samples frame_truth_ms frame_truth_cached; do
    col "$tmp/a" $c >/dev/null || fail "quality.csv has no $c"
done
/usr/bin/python3 - "$tmp/a" <<'PY' || fail "columns"
import csv, sys
import numpy as np
from PIL import Image
d = sys.argv[1]
r = {k: float(v) for k, v in next(csv.DictReader(open(d + "/quality.csv"))).items()}
assert 0 < r["frame_flip_ldr"] < 1 and 0 < r["frame_flip_hdr"] < 1, r
assert 0 < r["frame_relmse"] < 10, r
assert r["frame_truth_noise_relmse"] < r["frame_relmse"] / 10, r
assert r["frame_truth_cached"] == 0 and r["frame_truth_samples"] >= 16, r
m = np.asarray(Image.open(d + "/error_frame.png").convert("RGB"))
assert m.shape == (54, 96, 3), m.shape
c = np.asarray(Image.open(d + "/compare_frame.png").convert("RGB")).astype(int)
assert c.shape == (54, 288, 3), c.shape
assert c[:, 96:192].mean() > 10, "the truth's panel is black"
PY
ls "$tmp/cache"/frame-truth-*.bin >/dev/null 2>&1 || fail "no truth in the cache"

run "$tmp/b" --frame-truth-cache "$tmp/cache"
[ "$(col "$tmp/b" frame_truth_cached)" = 1 ] || fail "the second run traced the truth again"
for c in frame_flip_ldr frame_relmse; do
    [ "$(col "$tmp/a" $c)" = "$(col "$tmp/b" $c)" ] || fail "$c differs with the cached truth"
done
entry=$(ls "$tmp/cache"/frame-truth-*.bin)
/usr/bin/python3 -c 'import sys; p=sys.argv[1]; b=bytearray(open(p,"rb").read()); b[-5]^=0x40; open(p,"wb").write(b)' "$entry"
run "$tmp/c" --frame-truth-cache "$tmp/cache"
[ "$(col "$tmp/c" frame_truth_cached)" = 0 ] || fail "a damaged cache entry was read"
for c in frame_flip_ldr frame_relmse; do
    [ "$(col "$tmp/a" $c)" = "$(col "$tmp/c" $c)" ] || fail "$c differs after tracing the truth again"
done

run "$tmp/d" --set lighting.sun_turn_deg=60
/usr/bin/python3 - "$tmp/a" "$tmp/d" <<'PY' || fail "a frame lit from the wrong side is not judged worse"
import csv, sys
a, d = ({k: float(v) for k, v in next(csv.DictReader(open(p + "/quality.csv"))).items()} for p in sys.argv[1:])
for c in ("frame_flip_ldr", "frame_relmse"):
    assert d[c] > a[c] * 1.1, (c, a[c], d[c])
PY

set +e
msg=$("$judge" "$scene" --headless --bench --frames 2 --size 96x54 --out "$tmp/e" -q --frame-truth-cache "$tmp/x" 2>&1)
rc=$?
set -e
[ $rc = 1 ] || fail "--frame-truth-cache alone: exit $rc"
grep -q -- "--frame-metrics" <<<"$msg" || fail "the usage error does not name --frame-metrics: $msg"
echo "ok"
