#!/usr/bin/env bash
# The pnb-play window driven by scripted input (--script-input) under Xvfb: Esc and close quit
# with exit 0, a minimised window sleeps instead of rendering, the wheel steps speed and field of
# view, F12 saves a screenshot, dropped files that cannot be opened keep the scene (and say why),
# dropped .pnb/.obj files open (OBJ through a child pnb-convert), and the recording round trip:
# F9/K/--record-every in the window -> keyframe JSON -> `pnb-play --headless --bench --path FILE`
# (and `pnb-convert --path FILE`) replays it through the recorded camera positions.
# Usage: window_input_test.sh PNB_PLAY PNB_CONVERT SCENE.pnb SCENE.glb
set -euo pipefail
play=$1
convert=$2
scene=$3
source_scene=$4
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
if ! command -v xvfb-run >/dev/null; then
    echo "note: xvfb-run not installed; window input test skipped"
    exit 0
fi

# window NAME SCRIPT_TEXT [pnb-play options...]: runs the window with the script under Xvfb;
# stdout in $tmp/NAME.out, stderr in $tmp/NAME.err, exit code in $rc.
window() {
    local name=$1 text=$2
    shift 2
    printf '%s\n' "$text" >"$tmp/$name.script"
    set +e
    timeout 120 xvfb-run -a -s "-screen 0 320x240x24" "$play" "$scene" --size 128x96 --fixed-dt 0.05 \
        --script-input "$tmp/$name.script" "$@" >"$tmp/$name.out" 2>"$tmp/$name.err"
    rc=$?
    set -e
}
show() { cat "$tmp/$1.out" "$tmp/$1.err" >&2; }
summary() { # NAME FIELD: a number from the "window: ..." exit line (frames, waits, speed, fov)
    python3 - "$tmp/$1.out" "$2" <<'PY'
import re, sys
m = re.search(r"window: (\d+) frames rendered, (\d+) waits while minimised; speed (\S+) units/s, fov (\S+) deg",
              open(sys.argv[1]).read())
print(m.group({"frames": 1, "waits": 2, "speed": 3, "fov": 4}[sys.argv[2]]) if m else "missing")
PY
}

# --- --help lists the window's controls and options.
"$play" --help >"$tmp/help.out"
for word in F9 F12 Esc wheel --record-path --record-every --screenshot-dir --script-input "--path NAME|FILE"; do
    grep -q -- "$word" "$tmp/help.out" || fail "--help does not mention $word"
done

# --- A script that does not parse is a usage error naming the line.
printf '0 key NOPE down\n' >"$tmp/bad.script"
set +e
"$play" "$scene" --script-input "$tmp/bad.script" >"$tmp/bad.out" 2>&1
got=$?
set -e
[ "$got" -eq 1 ] || { cat "$tmp/bad.out"; fail "a bad script exited $got, expected 1"; }
grep -q "bad.script:1: unknown key 'NOPE'" "$tmp/bad.out" || fail "bad script line not named"

# --- Esc quits with 0 (this run is also the baseline speed and field of view).
window esc "0.2 key ESCAPE tap"
[ "$rc" -eq 0 ] || { show esc; fail "Esc: exit $rc"; }
frames=$(summary esc frames)
[ "$frames" != missing ] && [ "$frames" -ge 4 ] && [ "$frames" -le 6 ] || { show esc; fail "Esc: $frames frames"; }
speed0=$(summary esc speed)
fov0=$(summary esc fov)

# --- The window's close (what the close button sends) quits with 0.
window close "0.1 close"
[ "$rc" -eq 0 ] || { show close; fail "close: exit $rc"; }

# --- Minimised for 1 s of a 1.3 s run: it waits for events instead of rendering ~20 frames.
window minimised "0.1 iconify
1.1 restore
1.3 key ESCAPE tap"
[ "$rc" -eq 0 ] || { show minimised; fail "minimised: exit $rc"; }
frames=$(summary minimised frames)
waits=$(summary minimised waits)
[ "$frames" -le 10 ] && [ "$waits" -ge 1 ] || { show minimised; fail "minimised: $frames frames, $waits waits"; }

# --- Bad drops keep the scene and say why; F12 still shoots it afterwards.
head -c 1000 "$scene" >"$tmp/broken.pnb"
echo "not a scene" >"$tmp/notes.txt"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$tmp/tri.obj"
printf '{ "asset": ' >"$tmp/broken.gltf"
export PNB_CONVERT=$convert
window drops "0.05 drop $tmp/broken.pnb
0.10 drop $tmp/notes.txt
0.15 drop $tmp/broken.gltf
0.20 key F12 tap
0.30 key ESCAPE tap" --screenshot-dir "$tmp/shots"
[ "$rc" -eq 0 ] || { show drops; fail "bad drops: exit $rc"; }
grep -q "cannot open $tmp/broken.pnb: .*; keeping $scene" "$tmp/drops.err" || { show drops; fail "broken .pnb not reported"; }
grep -q "cannot open $tmp/notes.txt: drop a .pnb container" "$tmp/drops.err" || { show drops; fail ".txt not reported"; }
grep -q "cannot open $tmp/broken.gltf: pnb-convert failed (exit code" "$tmp/drops.err" || { show drops; fail "failed conversion not reported"; }
# A glob, not `ls | head`: with no match that pipeline fails and set -e would end the script
# before the check below could say why.
shots=("$tmp"/shots/pnb-play-*-001.png)
shot=${shots[0]}
[ -s "$shot" ] || { show drops; fail "F12 wrote no screenshot"; }
grep -q "screenshot $shot" "$tmp/drops.out" || { show drops; fail "screenshot path not printed"; }
grep -q "opened" "$tmp/drops.out" && fail "a bad drop claims to have opened"
# The scene really is the one it was: the same frame without the drops is the same image.
window nodrops "0.20 key F12 tap
0.30 key ESCAPE tap" --screenshot-dir "$tmp/shots_nodrops"
cmp -s "$shot" "$(ls "$tmp"/shots_nodrops/pnb-play-*-001.png)" || fail "the scene changed after bad drops"

# --- No converter anywhere: a clear message, the scene stays.
unset PNB_CONVERT
set +e
PATH=/usr/bin:/bin timeout 120 xvfb-run -a -s "-screen 0 320x240x24" "$play" "$scene" --size 128x96 \
    --fixed-dt 0.05 --script-input <(printf '0.05 drop %s\n0.1 key ESCAPE tap\n' "$tmp/tri.obj") \
    >"$tmp/noconv.out" 2>"$tmp/noconv.err"
rc=$?
set -e
[ "$rc" -eq 0 ] || { show noconv; fail "no converter: exit $rc"; }
grep -q "cannot open $tmp/tri.obj: pnb-convert was not found" "$tmp/noconv.err" || { show noconv; fail "missing converter not reported"; }

# --- Good drops: an OBJ converted in a child pnb-convert, then a .pnb.
export PNB_CONVERT=$convert
window opens "0.05 drop $tmp/tri.obj
0.10 key F12 tap
0.15 drop $scene
0.20 key ESCAPE tap" --screenshot-dir "$tmp/shots2"
[ "$rc" -eq 0 ] || { show opens; fail "good drops: exit $rc"; }
grep -q "opened $tmp/tri.obj: 1 draw items, 1 triangles" "$tmp/opens.out" || { show opens; fail "OBJ not opened"; }
grep -q "opened $scene:" "$tmp/opens.out" || { show opens; fail ".pnb not opened"; }
ls "$tmp"/shots2/pnb-play-*.png >/dev/null || fail "no screenshot of the dropped OBJ"

# --- Recording: fly, look, zoom and record (F9 start, periodic keys, K, F9 stop), then Esc.
window record "0.00 key F9 tap
0.10 key W down
0.60 key W up
0.70 button right down
0.70 cursor 100 50
0.75 cursor 140 60
0.80 button right up
0.85 key D down
1.25 key D up
1.30 key K tap
1.35 scroll 0 3
1.35 key E down
1.60 key E up
1.60 key LEFT_CONTROL down
1.65 scroll 0 2
1.70 key LEFT_CONTROL up
1.80 key F9 tap
1.90 key ESCAPE tap" --record-path "$tmp/rec.json" --record-every 0.5
[ "$rc" -eq 0 ] || { show record; fail "record: exit $rc"; }
[ -s "$tmp/rec.json" ] || { show record; fail "rec.json not written"; }
grep -q "saved camera path 'rec' (6 keys, 1.80 s) to $tmp/rec.json" "$tmp/record.out" || { show record; fail "save not reported"; }
# The wheel: 3 notches x1.25 on speed, 2 notches x0.9 on the field of view (with Ctrl).
python3 - "$speed0" "$fov0" "$(summary record speed)" "$(summary record fov)" <<'PY' || fail "wheel steps"
import sys
s0, f0, s1, f1 = map(float, sys.argv[1:])
assert abs(s1 / s0 - 1.25 ** 3) < 1e-4, (s0, s1)
assert abs(f1 / f0 - 0.81) < 1e-3, (f0, f1)
PY
# A second recording to the same file keeps the first one.
window record2 "0 key F9 tap
0.2 key F9 tap
0.3 key ESCAPE tap" --record-path "$tmp/rec.json"
grep -q "rec.json exists (kept); saving as $tmp/rec-2.json" "$tmp/record2.out" || { show record2; fail "overwrite not avoided"; }
[ -s "$tmp/rec-2.json" ] || fail "rec-2.json not written"

# Replay the file headless, and pack it into a container with pnb-convert --path and replay that.
"$play" "$scene" --headless --bench --path "$tmp/rec.json" --fixed-dt 0.05 --size 64x48 --no-plot \
    --out "$tmp/replay" -q || fail "replaying rec.json"
"$convert" "$source_scene" -o "$tmp/rec.pnb" --path "$tmp/rec.json" -q || fail "pnb-convert --path rec.json"
"$play" "$tmp/rec.pnb" --headless --bench --path rec --fixed-dt 0.05 --size 64x48 --no-plot \
    --out "$tmp/replay_converted" -q || fail "replaying the converted path"

python3 - "$tmp/record.out" "$tmp/rec.json" "$tmp/replay/frames.csv" "$tmp/replay_converted/frames.csv" <<'PY' || fail "recorded and replayed cameras differ"
import csv, json, math, re, sys
out, rec, *replays = sys.argv[1:]
keys = json.load(open(rec))["keys"]
assert [k["time"] for k in keys] == [0, 0.5, 1, 1.3, 1.5, 1.8], [k["time"] for k in keys]
# The window's camera at each key it printed (all but the stop key) is what the file holds.
printed = [(float(t), tuple(map(float, p.split(", "))))
           for t, p in re.findall(r"key \d+ at ([\d.]+) s \(([^)]*)\)", open(out).read())]
assert len(printed) == 5, printed
for (t, p), k in zip(printed, keys):
    assert abs(t - k["time"]) < 1e-6 and math.dist(p, k["position"]) < 1e-3, (t, p, k)
# The camera moved: forward, sideways after turning, and up.
assert math.dist(keys[0]["position"], keys[1]["position"]) > 0.1
assert abs(keys[-1]["position"][1] - keys[3]["position"][1]) > 0.1
assert abs(keys[-1]["yfov_degrees"] / keys[0]["yfov_degrees"] - 0.81) < 1e-3
for replay in replays:
    rows = list(csv.DictReader(open(replay)))
    matched = 0
    for k in keys:
        for r in rows:
            if abs(float(r["time_s"]) - k["time"]) < 1e-4:
                p = (float(r["camera_x"]), float(r["camera_y"]), float(r["camera_z"]))
                assert math.dist(p, k["position"]) < 1e-3, (replay, k, p)
                assert abs(float(r["camera_yfov_deg"]) - k["yfov_degrees"]) < 1e-3, (replay, k, r)
                matched += 1
    # Frames cover [0, duration): every key but the last one lands on a frame.
    assert matched == len(keys) - 1, (replay, matched)
print("recorded keys replayed:", len(keys) - 1, "x", len(replays))
PY
echo "pnb-play window input: ok"
