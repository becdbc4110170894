#!/usr/bin/env bash
# pnb-make-stream-scene end to end, small: a ~64 MiB scene is valid (pnb-inspect --verify), its
# TMIP chunks come smallest level first, the same arguments give the same bytes (also with one
# thread instead of two), bad arguments exit 1, an unwritable target exits 2 without a file, and
# pnb-play draws a frame of it headless. Then the same for a tiny scene with --lod-rocks, whose
# rocks' details (MDET, one a rock) sit between the smallest texel levels and the larger ones.
# Usage: stream_scene_test.sh PNB_MAKE_STREAM_SCENE PNB_INSPECT PNB_PLAY
set -euo pipefail
make=$1
inspect=$2
play=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

expect_exit() { # code, command...
    local want=$1
    shift
    set +e
    "$@" >"$tmp/out" 2>&1
    local got=$?
    set -e
    [ "$got" -eq "$want" ] || { cat "$tmp/out"; fail "'$*' exited $got, expected $want"; }
}

# Usage errors.
expect_exit 0 "$make" --help
expect_exit 1 "$make"
expect_exit 1 "$make" "$tmp/x.pnb"                      # neither --size nor --textures
expect_exit 1 "$make" "$tmp/x.pnb" --size 1G --textures 3
expect_exit 1 "$make" "$tmp/x.pnb" --size 12Q
expect_exit 1 "$make" "$tmp/x.pnb" --textures 2 --texture-size 1000
expect_exit 1 "$make" "$tmp/x.pnb" --textures 2 --frobnicate
grep -q "unknown option '--frobnicate'" "$tmp/out" || fail "unknown option not named"
expect_exit 1 "$make" "$tmp/x.pnb" --textures 2 --lod-rocks --rock-triangles 99
expect_exit 1 "$make" "$tmp/x.pnb" --textures 2 --lod-rocks --rock-triangles 1000001
expect_exit 1 "$make" "$tmp/x.pnb" --textures 2 --lod-rocks --rock-triangles 2k
expect_exit 1 "$make" "$tmp/x.pnb" --textures 2 --lod-rocks --rock-triangles
expect_exit 1 "$make" "$tmp/x.pnb" --textures 2 --rock-triangles 2000 # without --lod-rocks
[ ! -e "$tmp/x.pnb" ] || fail "a usage error wrote a file"
# Write error: the target's directory does not exist.
expect_exit 2 "$make" "$tmp/no/such/dir/x.pnb" --textures 2 --texture-size 64
grep -q "cannot write" "$tmp/out" || fail "write error not reported"

# A ~64 MiB scene, twice (two threads, then one): identical bytes.
expect_exit 0 "$make" "$tmp/a.pnb" --size 64M --texture-size 1024
cat "$tmp/out"
expect_exit 0 "$make" "$tmp/b.pnb" --size 64M --texture-size 1024 --threads 1 -q
[ ! -s "$tmp/out" ] || fail "-q printed something"
cmp "$tmp/a.pnb" "$tmp/b.pnb" || fail "two runs with the same arguments differ"
size=$(stat -c %s "$tmp/a.pnb")
[ "$size" -ge $((64 * 1024 * 1024)) ] || fail "file is $size bytes, below --size 64M"
[ "$(find "$tmp" -name '.a.pnb.tmp.*' | wc -l)" -eq 0 ] || fail "temporary left behind"

expect_exit 0 "$inspect" --verify "$tmp/a.pnb"
grep -q "verify: ok" "$tmp/out" || fail "pnb-inspect --verify did not say ok"

# TMIP order: smallest level first across all textures. All textures share one size, so a
# level's chunks all have one raw size: sizes never decrease, and each of the 11 levels of a
# 1024 texture appears once per texture.
"$inspect" --json "$tmp/a.pnb" >"$tmp/a.json"
python3 - "$tmp/a.json" <<'PY' || fail "TMIP order"
import json, sys
j = json.load(open(sys.argv[1]))
tags = [c["tag"] for c in j["chunks"] if c["tag"] != "TOCX"]
order = ["STRS", "INFO", "RSET", "SHDR", "PROG", "TEXR", "MATL", "MESH", "LGHT", "CAMR", "NODE",
         "PATH", "TMIP"]
ranks = [order.index(t) for t in tags]
assert ranks == sorted(ranks), "chunk kinds out of FORMAT.md 4.1 order"
textures = tags.count("TEXR")
sizes = [c["raw_size"] for c in j["chunks"] if c["tag"] == "TMIP"]
assert sizes == sorted(sizes), "TMIP chunks not smallest level first"
assert len(sizes) == textures * 11, (len(sizes), textures)
for level in range(11):
    run = sizes[level * textures:(level + 1) * textures]
    assert len(set(run)) == 1, "level %d mixed with another" % level
assert sizes[-1] == 32 + 1024 * 1024 * 4, sizes[-1]
print("TMIP order ok: %d textures x 11 levels" % textures)
PY

# One headless frame.
expect_exit 0 "$play" "$tmp/a.pnb" --headless --frames 1 --size 320x180 \
    --screenshot "$tmp/shot.png" -q
[ -s "$tmp/shot.png" ] || fail "no screenshot"

# --lod-rocks: 4 panels, 4 rocks of about 2000 triangles, twice (two threads, then one).
rocks=(--textures 4 --texture-size 64 --lod-rocks --rock-triangles 2000)
expect_exit 0 "$make" "$tmp/r.pnb" "${rocks[@]}"
cat "$tmp/out"
expect_exit 0 "$make" "$tmp/r1.pnb" "${rocks[@]}" --threads 1 -q
cmp "$tmp/r.pnb" "$tmp/r1.pnb" || fail "two --lod-rocks runs with the same arguments differ"
[ "$(find "$tmp" -name '.pnb-make-stream-scene-rocks.*' | wc -l)" -eq 0 ] ||
    fail "the rocks' temporary file was left behind"
expect_exit 0 "$inspect" --verify "$tmp/r.pnb"
grep -q "verify: ok" "$tmp/out" || fail "pnb-inspect --verify did not say ok (--lod-rocks)"
"$inspect" --json "$tmp/r.pnb" >"$tmp/r.json"
python3 - "$tmp/r.json" <<'PY' || fail "MDET placement"
import json, sys
j = json.load(open(sys.argv[1]))
chunks = [c for c in j["chunks"] if c["tag"] != "TOCX"]
tags = [c["tag"] for c in chunks]
assert tags.count("MESH") == 4 + 1 + 4, tags.count("MESH")  # panels, ground, rocks
mdet = [i for i, t in enumerate(tags) if t == "MDET"]
assert len(mdet) == 4, "%d MDET chunks, expected one per rock" % len(mdet)
tmip = [(i, c["raw_size"]) for i, c in enumerate(chunks) if c["tag"] == "TMIP"]
smallest = min(size for _, size in tmip)
last_smallest = max(i for i, size in tmip if size == smallest)
first_larger = min(i for i, size in tmip if size > smallest)
assert all(last_smallest < i < first_larger for i in mdet), \
    "MDET at %s, not between the last smallest TMIP (%d) and the first larger one (%d)" % (
        mdet, last_smallest, first_larger)
# Each rock's MESH is its coarse proxy: smaller than its detail.
rock_meshes = [c["raw_size"] for c in chunks if c["tag"] == "MESH"][5:]
details = [chunks[i]["raw_size"] for i in mdet]
assert all(m < d for m, d in zip(rock_meshes, details)), (rock_meshes, details)
print("MDET order ok: %d details after the last smallest TMIP" % len(mdet))
PY
expect_exit 0 "$play" "$tmp/r.pnb" --headless --frames 1 --size 320x180 \
    --screenshot "$tmp/rshot.png" -q
[ -s "$tmp/rshot.png" ] || fail "no screenshot (--lod-rocks)"
echo "ok"
