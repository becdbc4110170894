#!/usr/bin/env bash
# Streaming a large container (issue 14): a generated scene of >= 1 GiB, made here in the temporary
# directory and deleted at the end, draws its first frame before 10 % of its bytes have been read
# — from the file with and without a texture budget, and from a pipe (`cat | pnb-play -`); a
# short --bench run along its path writes the streaming figures and stays within the budget.
# Usage: stream_first_frame_test.sh PNB_MAKE_STREAM_SCENE PNB_PLAY
set -euo pipefail
make=$1
play=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

scene=$tmp/large.pnb
"$make" "$scene" --size 1G -q
bytes=$(stat -c %s "$scene")
[ "$bytes" -ge $((1 << 30)) ] || fail "the scene has $bytes bytes, fewer than 1 GiB"

# "streaming: first frame after reading R of T MiB (P %)" or "... reading R MiB" (a pipe).
check_first_frame() { # label, output file
    local line read_mib
    line=$(grep '^streaming: first frame after reading' "$2") || { cat "$2"; fail "$1: no streaming line"; }
    read_mib=$(echo "$line" | awk '{print $6}')
    echo "$1: $line"
    awk -v r="$read_mib" -v b="$bytes" 'BEGIN { exit !(r * 1048576 < 0.10 * b) }' ||
        fail "$1: the first frame came after $read_mib MiB of $((bytes >> 20)) MiB (10 % is the limit)"
}

"$play" "$scene" --headless --stream --frames 1 --size 256x144 >"$tmp/file.txt" 2>&1 ||
    { cat "$tmp/file.txt"; fail "streaming the file failed"; }
check_first_frame "file, no budget" "$tmp/file.txt"

"$play" "$scene" --headless --stream --frames 1 --size 256x144 --set stream.budget_mib=128 >"$tmp/budget.txt" 2>&1 ||
    { cat "$tmp/budget.txt"; fail "streaming the file with a budget failed"; }
check_first_frame "file, 128 MiB budget" "$tmp/budget.txt"

{ cat "$scene" || true; } | "$play" - --headless --frames 1 --size 256x144 >"$tmp/pipe.txt" 2>&1 ||
    { cat "$tmp/pipe.txt"; fail "streaming from a pipe failed"; }
check_first_frame "pipe" "$tmp/pipe.txt"

# A short run along the path with a budget: the figures are written and the budget holds.
"$play" "$scene" --headless --stream --bench --out "$tmp/bench" --frames 30 --size 256x144 --no-plot -q \
    --set stream.budget_mib=128 --set stream.upload_mib=16 || fail "the streaming benchmark failed"
python3 - "$tmp/bench/summary.json" "$tmp/bench/frames.csv" <<'PY'
import csv, json, sys
s = json.load(open(sys.argv[1]))["streaming"]
budget = 128 << 20
assert s["texture_budget_bytes"] == budget, s
assert 0 < s["peak_texture_bytes"] <= budget, s
assert s["first_frame_bytes_read"] < 0.10 * s["file_bytes"], s
assert s["uploaded_bytes"] > 0, s
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == 30
for r in rows:
    assert int(r["resident_texture_bytes"]) <= budget, r
    assert int(r["stream_upload_bytes"]) <= (16 << 20) + (1 << 20), r
print("bench: peak texture storage %.1f of %d MiB, %d evictions, %.1f MiB uploaded"
      % (s["peak_texture_bytes"] / 2**20, budget >> 20, s["evictions"], s["uploaded_bytes"] / 2**20))
PY
echo "ok"
