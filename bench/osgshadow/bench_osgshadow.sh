#!/usr/bin/env bash
# OpenSceneGraph's osgShadow as a measured peer: frame time of the stock `osgshadow` example
# (Debian package openscenegraph 3.6.5) at 1280x720 under Xvfb + Mesa llvmpipe, on one of our
# procedural scenes, seen from the scene's own camera and lit by the scene's own sun, for
#   none    no shadow technique (--no-shadows: same ShadowedScene, same lighting) - the baseline
#   vdsm    ViewDependentShadowMap, 2 maps of 2048^2 (--vdsm --num-sm 2 --mapres 2048)
#   pssm    ParallelSplitShadowMap, 3 splits of 2048^2 (--pssm --mapcount 3 --mapres 2048)
#   lispsm  LightSpacePerspectiveShadowMapDB, 1 map of 2048^2 (--lispsm --mapres 2048)
# Findings, the camera and light numbers and the reasons behind every step:
# bench/osgshadow/NOTES.md.
#
# How: pnb-make-scene writes the .glb; bench/osgshadow/glb2obj.py turns it into an OBJ rotated so
# the sun travels along -Z (the only light direction osgshadow applies consistently to every
# technique, see NOTES.md), plus an AnimationPathManipulator file holding the scene's camera
# (osgshadow -p). bench/osgshadow/frame_clock.c, an LD_PRELOAD shim around glXSwapBuffers,
# timestamps every frame (glFinish before each swap), stops osgshadow after a pinned number of
# frames, grabs the last frame and logs the GL state that proves the camera, light and shadow
# passes. An untimed warm-up run of each technique, then rounds: each shadow technique back to
# back with its own `none` run (which goes first alternates by round; the technique order
# rotates); per run the first --warmup frame intervals are dropped.
# bench/osgshadow/summarize.py reports per technique the median ms/frame (median of the per-run
# medians), the ratio to `none` (median over rounds of the back-to-back pair ratios), the same for
# process CPU time per frame, checks camera/light/shadow passes against the request (exit 1 if
# they differ), and cross-checks the shim clock against whole-process wall time of N and 2N frames.
#
# Output (out/osgshadow/ unless --out): summary.json (everything, with the exact command lines),
# table.md, screenshots/<technique>.png (the same camera for each), runs/ (raw per-run clocks and
# logs), scene/ (the generated .glb/.obj/.mtl, camera.path, camera.json). Nothing is committed.
#
#   scripts/bench-osgshadow                          # street-canyon, 5 rounds, 100 frames/run
#   scripts/bench-osgshadow --scene box-room --rounds 3 --frames 150 --warmup 30
#   scripts/bench-osgshadow --glb my.glb --camera cam --techniques "none vdsm"
# Options: --scene NAME (pnb-make-scene name, default street-canyon) | --glb FILE (use this .glb
# instead) | --camera NODE (camera node name; default the first) | --frames N (frames per run:
# swap N ends the run untimed, so N - 2 intervals, warm-up included; default 100) | --warmup N
# (intervals dropped per run, default 20) | --rounds N (default 5; >= 3 recommended) |
# --size WxH (default 1280x720) | --mapres N (default 2048) | --vdsm-maps N (default 2) |
# --pssm-splits N (default 3) | --techniques "none vdsm pssm lispsm" (none is
# required: it is the baseline) | --threading SingleThreaded|DrawThreadPerContext|... (OSG
# threading model, default SingleThreaded) | --no-crosscheck | --out DIR.
# Needs: osgshadow (openscenegraph), Xvfb (xvfb), gcc and GL/glx.h (libgl-dev), python3.
# About 2-4 minutes on 2 llvmpipe cores with the defaults. The machine is shared and noisy:
# compare the ratios, not absolute times across runs.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"

die() {
    echo "bench-osgshadow: $*" >&2
    exit 1
}

scene=street-canyon
glb=
camera=
frames=100
warmup=20
rounds=5
size=1280x720
mapres=2048
vdsm_maps=2
pssm_splits=3
techniques="none vdsm pssm lispsm"
threading=SingleThreaded
crosscheck=1
out=out/osgshadow
while [ $# -gt 0 ]; do
    case "$1" in
    --scene) scene=$2; shift 2 ;;
    --glb) glb=$2; shift 2 ;;
    --camera) camera=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --warmup) warmup=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --mapres) mapres=$2; shift 2 ;;
    --vdsm-maps) vdsm_maps=$2; shift 2 ;;
    --pssm-splits) pssm_splits=$2; shift 2 ;;
    --techniques) techniques=$2; shift 2 ;;
    --threading) threading=$2; shift 2 ;;
    --no-crosscheck) crosscheck=0; shift ;;
    --out) out=$2; shift 2 ;;
    -h | --help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown argument $1 (see the header of $0)" ;;
    esac
done

# --- prerequisites ---------------------------------------------------------------------------
command -v osgshadow >/dev/null ||
    die "osgshadow not found: install the Debian package openscenegraph (apt-get install openscenegraph)"
command -v Xvfb >/dev/null || die "Xvfb not found: install the Debian package xvfb"
command -v gcc >/dev/null || die "gcc not found (needed for the frame_clock shim): apt-get install gcc"
[ -f /usr/include/GL/glx.h ] || die "GL/glx.h not found: install the Debian package libgl-dev"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
command -v "$py" >/dev/null || die "python3 not found"

for n in "$frames" "$warmup" "$rounds" "$mapres" "$vdsm_maps" "$pssm_splits"; do
    [[ "$n" =~ ^[0-9]+$ ]] || die "expected a number, got '$n'"
done
[ "$frames" -ge $((warmup + 10)) ] || die "--frames must be at least --warmup + 10"
[ "$rounds" -ge 1 ] || die "--rounds must be >= 1"
[[ "$size" =~ ^([0-9]+)x([0-9]+)$ ]] || die "--size must be WxH"
width=${BASH_REMATCH[1]}
height=${BASH_REMATCH[2]}
declare -A targs=(
    [none]="--no-shadows"
    [vdsm]="--vdsm --num-sm $vdsm_maps --mapres $mapres"
    [pssm]="--pssm --mapcount $pssm_splits --mapres $mapres"
    [lispsm]="--lispsm --mapres $mapres"
)
declare -A labels=(
    [none]="no shadows"
    [vdsm]="ViewDependentShadowMap, $vdsm_maps x ${mapres}²"
    [pssm]="ParallelSplitShadowMap, $pssm_splits x ${mapres}²"
    [lispsm]="LiSPSM (DrawBounds), 1 x ${mapres}²"
)
read -r -a techs <<<"$techniques"
[ "${techs[0]:-}" = none ] || die "--techniques must start with none (the baseline)"
for t in "${techs[@]}"; do
    [ -n "${targs[$t]:-}" ] || die "unknown technique $t (none vdsm pssm lispsm)"
done

mkdir -p "$out"
out=$(cd "$out" && pwd)
rm -rf "$out/runs" "$out/screenshots" "$out/work"
mkdir -p "$out/scene" "$out/runs" "$out/work"

# --- scene -----------------------------------------------------------------------------------
if [ -z "$glb" ]; then
    gen=build/release/assets_src/pnb-make-scene
    if [ ! -x "$gen" ]; then
        echo "bench-osgshadow: building pnb-make-scene (release preset)"
        [ -f build/release/build.ninja ] || nice -n 10 cmake --preset release >/dev/null
        nice -n 10 cmake --build --preset release --target pnb-make-scene
    fi
    glb=$out/scene/$scene.glb
    "$gen" "$scene" "$glb" >/dev/null
fi
[ -f "$glb" ] || die "$glb not found"
"$py" bench/osgshadow/glb2obj.py "$glb" "$out/scene/scene.obj" --frame sun-down \
    --path "$out/scene/camera.path" --json "$out/scene/camera.json" ${camera:+--camera "$camera"}
yfov=$("$py" -c 'import json,sys; print(json.load(open(sys.argv[1]))["camera"]["yfov_deg"])' \
    "$out/scene/camera.json")

# --- shim and X server -----------------------------------------------------------------------
shim=$out/work/frame_clock.so
gcc -shared -fPIC -O2 -Wall -o "$shim" bench/osgshadow/frame_clock.c -ldl -lGL

xdir=$(mktemp -d)
Xvfb -displayfd 3 -screen 0 "$((width + 64))x$((height + 64))x24" -nolisten tcp \
    3>"$xdir/display" >"$xdir/xvfb.log" 2>&1 &
xpid=$!
# shellcheck disable=SC2317 # called by the EXIT trap
cleanup() {
    kill "$xpid" 2>/dev/null || true
    wait "$xpid" 2>/dev/null || true
    rm -rf "$xdir"
}
trap cleanup EXIT
for _ in $(seq 100); do
    [ -s "$xdir/display" ] && break
    kill -0 "$xpid" 2>/dev/null || die "Xvfb failed to start: $(cat "$xdir/xvfb.log")"
    sleep 0.1
done
[ -s "$xdir/display" ] || die "Xvfb did not report a display within 10 s"
DISPLAY=:$(head -n1 "$xdir/display")
export DISPLAY
export vblank_mode=0

common=(--"$threading" --noUpdate --window 0 0 "$width" "$height" --fov "$yfov"
    -p "$out/scene/camera.path" -O noRotation "$out/scene/scene.obj")
rel() { realpath --relative-to="$root" "$1"; }
# A technique's round-1 command line, as run (paths relative to the repository root).
command_of() {
    local t=$1 name=$1-r1
    [ "$t" = none ] && [ "${#techs[@]}" -gt 1 ] && name=none-r1-${techs[1]}
    # shellcheck disable=SC2086
    printf '%q ' DISPLAY="$DISPLAY" vblank_mode=0 LD_PRELOAD="$(rel "$shim")" \
        FRAME_CLOCK_OUT="$(rel "$out")/runs/$name.txt" FRAME_CLOCK_FRAMES="$frames" \
        FRAME_CLOCK_PPM="$(rel "$out")/runs/$t.ppm" \
        osgshadow ${targs[$t]} --"$threading" --noUpdate --window 0 0 "$width" "$height" \
        --fov "$yfov" -p "$(rel "$out")/scene/camera.path" -O noRotation "$(rel "$out")/scene/scene.obj"
}

runs_tsv=$out/runs/runs.tsv
: >"$runs_tsv"
# run_one TECHNIQUE ROUND PAIR FRAMES KIND NAME [PPM]: one osgshadow process, pinned to FRAMES
# swaps; KIND round | crosscheck | warmup (warm-up runs are not recorded).
run_one() {
    local t=$1 round=$2 pair=$3 n=$4 kind=$5 name=$6 ppm=${7:-}
    local clock=$out/runs/$name.txt log=$out/runs/$name.log t0 t1
    rm -f "$clock"
    t0=$(date +%s%N)
    # shellcheck disable=SC2086
    if ! FRAME_CLOCK_OUT=$clock FRAME_CLOCK_FRAMES=$n FRAME_CLOCK_PPM=$ppm LD_PRELOAD=$shim \
        timeout $((n * 2 + 120)) osgshadow ${targs[$t]} "${common[@]}" >"$log" 2>&1 ||
        [ ! -s "$clock" ]; then
        tail -n 20 "$log" >&2
        die "osgshadow ($t, $kind $round) failed or stopped before frame $n; log: $log"
    fi
    t1=$(date +%s%N)
    if [ "$kind" = warmup ]; then
        rm -f "$clock" "$log"
        return
    fi
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$t" "$round" "$pair" "$kind" "$n" \
        "runs/$name.txt" "$((t1 - t0))" >>"$runs_tsv"
}

load_start=$(cut -d' ' -f1-3 /proc/loadavg)
echo "bench-osgshadow: $scene at ${width}x$height, $rounds rounds, $frames frames/run (first $warmup intervals dropped), DISPLAY=$DISPLAY"
# Untimed warm-up: fills Mesa's shader cache and the page cache so round 1 is not special.
for t in "${techs[@]}"; do
    run_one "$t" 0 - $((warmup + 12)) warmup "$t-warmup"
done
# Rounds: every shadow technique runs back to back with its own no-shadow run (the pair's
# ratio is the technique's slowdown at that moment); the no-shadow run goes first in odd
# rounds and second in even rounds, and the technique order rotates by one each round.
shadowed=("${techs[@]:1}")
for round in $(seq 1 "$rounds"); do
    if [ "${#shadowed[@]}" -eq 0 ]; then
        run_one none "$round" - "$frames" round "none-r$round" "$([ "$round" = 1 ] && echo "$out/runs/none.ppm")"
        continue
    fi
    k=$(((round - 1) % ${#shadowed[@]}))
    order=("${shadowed[@]:k}" "${shadowed[@]:0:k}")
    for t in "${order[@]}"; do
        ppm=
        base_ppm=
        if [ "$round" = 1 ]; then
            ppm=$out/runs/$t.ppm
            [ "$t" = "${shadowed[0]}" ] && base_ppm=$out/runs/none.ppm
        fi
        if [ $((round % 2)) = 1 ]; then
            run_one none "$round" "$t" "$frames" round "none-r$round-$t" "$base_ppm"
            run_one "$t" "$round" "$t" "$frames" round "$t-r$round" "$ppm"
        else
            run_one "$t" "$round" "$t" "$frames" round "$t-r$round" "$ppm"
            run_one none "$round" "$t" "$frames" round "none-r$round-$t" "$base_ppm"
        fi
    done
    echo "  round $round done: ${order[*]} (each paired with none)"
done
if [ "$crosscheck" = 1 ]; then
    for t in "${techs[@]}"; do
        run_one "$t" 0 - "$frames" crosscheck "$t-x$frames"
        run_one "$t" 0 - "$((frames * 2))" crosscheck "$t-x$((frames * 2))"
    done
    echo "  wall-clock cross-check done"
fi
load_end=$(cut -d' ' -f1-3 /proc/loadavg)

# --- run.json, then the summary --------------------------------------------------------------
commands_json=$(for t in "${techs[@]}"; do
    printf '%s\t%s\t%s\n' "$t" "$(command_of "$t")" "${labels[$t]}"
done)
expected=$(printf 'vdsm\t%sx%s\t%s\npssm\t%sx%s\t%s\nlispsm\t%sx%s\t1\nnone\t-\t0\n' \
    "$mapres" "$mapres" "$vdsm_maps" "$mapres" "$mapres" "$pssm_splits" "$mapres" "$mapres")
RUNS_TSV=$runs_tsv OUT=$out ROOT=$root COMMANDS=$commands_json EXPECTED=$expected \
    TECHS="${techs[*]}" FRAMES=$frames WARMUP=$warmup ROUNDS=$rounds WIDTH=$width HEIGHT=$height \
    MAPRES=$mapres VDSM_MAPS=$vdsm_maps PSSM_SPLITS=$pssm_splits THREADING=$threading \
    SCENE=$scene GLB=$(rel "$glb") LOAD_START=$load_start LOAD_END=$load_end \
    OSG_VERSION=$(dpkg-query -W -f '${Version}' openscenegraph 2>/dev/null || echo unknown) \
    "$py" - <<'EOF'
import json, os, platform
e = os.environ
runs = []
for line in open(e['RUNS_TSV']):
    t, rnd, pair, kind, n, clock, wall = line.rstrip('\n').split('\t')
    runs.append({'technique': t, 'round': int(rnd), 'pair': None if pair == '-' else pair,
                 'kind': kind,
                 'frames': int(n), 'clock': clock, 'wall_s': int(wall) / 1e9})
commands, labels = {}, {}
for line in e['COMMANDS'].splitlines():
    t, cmd, label = line.split('\t')
    commands[t] = cmd.strip()
    labels[t] = label
expected = {}
for line in e['EXPECTED'].splitlines():
    t, size, count = line.split('\t')
    expected[t] = [size, int(count)] if size != '-' else None
run = {
    'repo_root': e['ROOT'],
    'techniques': e['TECHS'].split(),
    'labels': labels,
    'commands': commands,
    'expected_shadow_passes': expected,
    'settings': {'scene': e['SCENE'], 'glb': e['GLB'], 'frames_per_run': int(e['FRAMES']),
                 'warmup': int(e['WARMUP']), 'rounds': int(e['ROUNDS']),
                 'window': [int(e['WIDTH']), int(e['HEIGHT'])], 'mapres': int(e['MAPRES']),
                 'vdsm_maps': int(e['VDSM_MAPS']), 'pssm_splits': int(e['PSSM_SPLITS']),
                 'osg_threading': e['THREADING'],
                 'order': 'per round, each shadow technique back to back with a none run (none '
                          'first in odd rounds, second in even rounds); technique order '
                          'rotates by one each round; an untimed warm-up run of each '
                          'technique comes first'},
    'machine': {'cpus': os.cpu_count(), 'kernel': platform.release(),
                'loadavg_start': e['LOAD_START'], 'loadavg_end': e['LOAD_END'],
                'openscenegraph_package': e['OSG_VERSION']},
    'environment': {'LP_NUM_THREADS': e.get('LP_NUM_THREADS', '(unset: llvmpipe uses one thread per CPU)'),
                    'vblank_mode': '0', 'display': 'Xvfb, 24-bit, started by the script'},
    'runs': runs,
}
json.dump(run, open(os.path.join(e['OUT'], 'run.json'), 'w'), indent=1)
EOF
status=0
"$py" bench/osgshadow/summarize.py "$out" || status=$?
echo "bench-osgshadow: $(rel "$out")/summary.json, table.md, screenshots/"
exit "$status"
