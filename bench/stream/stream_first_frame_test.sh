#!/usr/bin/env bash
# Streaming a large container (issue 14): a generated scene of >= 1 GiB, made here in the temporary
# directory and deleted at the end, draws its first frame before 10 % of its bytes have been read
# — from the file with and without a texture budget, and from a pipe (`cat | pnb-play -`); a
# short --bench run along its path writes the streaming figures and stays within the budget.
# A chunk damaged mid-stream ends the run with exit code 2 and a message naming the chunk and its
# offset, from the file and from a pipe.
# Usage: stream_first_frame_test.sh PNB_MAKE_STREAM_SCENE PNB_PLAY PNB_INSPECT
set -euo pipefail
make=$1
play=$2
inspect=$3
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
assert s["budget_bytes"] == budget, s
assert 0 < s["peak_bytes"] <= budget, s
assert s["first_frame_bytes_read"] < 0.10 * s["file_bytes"], s
assert s["uploaded_bytes"] > 0, s
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == 30
for r in rows:
    assert int(r["resident_bytes"]) <= budget, r
    assert int(r["stream_upload_bytes"]) <= (16 << 20) + (1 << 20), r
print("bench: peak texture storage %.1f of %d MiB, %d evictions, %.1f MiB uploaded"
      % (s["peak_bytes"] / 2**20, budget >> 20, s["evictions"], s["uploaded_bytes"] / 2**20))
PY
# Damage mid-stream: a byte of the last texel chunk's payload (a level 0, after the first frame).
small=$tmp/small.pnb
"$make" "$small" --textures 4 --texture-size 512 -q
read -r seq off size < <("$inspect" "$small" --json | python3 -c '
import json, sys
c = [c for c in json.load(sys.stdin)["chunks"] if c["tag"] == "TMIP"][-1]
print(c["index"], c["payload_offset"], c["stored_size"])')
python3 - "$small" $((off + size / 2)) <<'PY'
import sys
with open(sys.argv[1], "r+b") as f:
    f.seek(int(sys.argv[2]))
    b = f.read(1)
    f.seek(int(sys.argv[2]))
    f.write(bytes([b[0] ^ 0x5A]))
PY
for source in file pipe; do
    set +e
    if [ $source = file ]; then
        "$play" "$small" --headless --stream --frames 400 --size 128x72 --set stream.upload_mib=0.25 >"$tmp/damaged.txt" 2>&1
    else
        { cat "$small" || true; } | "$play" - --headless --frames 400 --size 128x72 --set stream.upload_mib=0.25 >"$tmp/damaged.txt" 2>&1
    fi
    code=$?
    set -e
    [ $code -eq 2 ] || { cat "$tmp/damaged.txt"; fail "damaged chunk ($source): exit $code, expected 2"; }
    grep -q "chunk $seq 'TMIP'" "$tmp/damaged.txt" && grep -q "at byte $off" "$tmp/damaged.txt" ||
        { cat "$tmp/damaged.txt"; fail "damaged chunk ($source): the message does not name chunk $seq at byte $off"; }
    echo "damaged ($source): $(grep -m1 'pnb-play:' "$tmp/damaged.txt")"
done
echo "ok"
