#!/bin/sh
# make_scene_cli_test.sh PNB_MAKE_SCENE WORK_DIR
#
# pnb-make-scene's documented interface: --list, --help, exit codes 0 ok / 2 usage / 4 output,
# and the summary line (triangles, bytes).
set -u
tool=${1:?usage: make_scene_cli_test.sh PNB_MAKE_SCENE WORK_DIR}
dir=${2:?}
status=0
rm -rf "$dir"
mkdir -p "$dir"

# expect CODE ARGS...: runs the tool, keeps stdout/stderr in $dir/out and $dir/err.
expect() {
    want=$1
    shift
    "$tool" "$@" >"$dir/out" 2>"$dir/err"
    got=$?
    if [ "$got" != "$want" ]; then
        echo "FAIL: pnb-make-scene $* exited $got, expected $want" >&2
        cat "$dir/err" >&2
        status=1
    fi
}
# contains FILE TEXT
contains() {
    grep -qF -- "$2" "$dir/$1" || { echo "FAIL: $1 lacks '$2'" >&2; cat "$dir/$1" >&2; status=1; }
}

expect 0 --list
for scene in street-canyon flat-city box-room terrain grazing-plane load-test light-field crowd moving-light; do
    contains out "$scene"
done
expect 0 --help
contains out "usage: pnb-make-scene"

expect 2
contains err "Error:"
expect 2 box-room
expect 2 no-such-scene "$dir/x.glb"
contains err "unknown scene"
expect 2 box-room "$dir/x.glb" --triangles
expect 2 box-room "$dir/x.glb" --triangles 0
expect 2 box-room "$dir/x.glb" --triangles -5
expect 2 box-room "$dir/x.glb" --seed 12abc
expect 2 box-room "$dir/x.glb" --bogus
expect 2 box-room "$dir/x.glb" extra-argument
expect 2 box-room "$dir/x.glb" --lights 3
contains err "light-field only"
expect 2 light-field "$dir/x.glb" --lights 4097
expect 2 light-field "$dir/x.glb" --lights
expect 2 box-room "$dir/x.glb" --texture-size 64
contains err "load-test only"
expect 2 load-test "$dir/x.glb" --texture-size 3
expect 2 load-test "$dir/x.glb" --texture-size 4097
expect 2 street-canyon "$dir/x.glb" --unit-scale 0
expect 2 street-canyon "$dir/x.glb" --unit-scale nan
expect 2 street-canyon "$dir/x.glb" --origin 1,2
expect 2 street-canyon "$dir/x.glb" --sun-elevation 91
contains err "0..90"
expect 2 street-canyon "$dir/x.glb" --camera-near -1
[ -e "$dir/x.glb" ] && { echo "FAIL: a usage error wrote a file" >&2; status=1; }

expect 4 box-room "$dir/no/such/dir/x.glb"
contains err "Error:"

expect 0 light-field "$dir/lights.glb" --lights 3
contains out "light-field"
expect 0 street-canyon "$dir/canyon.glb" --triangles 20000 --seed 7
contains out "triangles rendered"
size=$(wc -c <"$dir/canyon.glb" | tr -d ' ')
contains out "$size bytes"
# Deterministic: the same arguments give identical bytes.
expect 0 street-canyon "$dir/canyon2.glb" --triangles 20000 --seed 7
if ! cmp -s "$dir/canyon.glb" "$dir/canyon2.glb"; then
    echo "FAIL: output differs between runs" >&2
    status=1
fi
# --texture-size: the load test's images shrink with it (64² and 16² PNGs of the same scene).
expect 0 load-test "$dir/lt64.glb" --triangles 2000 --texture-size 64
expect 0 load-test "$dir/lt16.glb" --triangles 2000 --texture-size 16
if [ "$(wc -c <"$dir/lt16.glb")" -ge "$(wc -c <"$dir/lt64.glb")" ]; then
    echo "FAIL: --texture-size 16 did not make smaller images than 64" >&2
    status=1
fi
# --count: crowd only, 1..1000; the walkers follow it (one skin each), the bytes are repeatable.
expect 2 box-room "$dir/x.glb" --count 3
contains err "crowd only"
expect 2 crowd "$dir/x.glb" --count 0
contains err "from 1 to 1000"
expect 2 crowd "$dir/x.glb" --count 1001
expect 0 crowd "$dir/crowd1.glb" --count 1
expect 0 crowd "$dir/crowd10.glb" --count 10
expect 0 crowd "$dir/crowd10b.glb" --count 10
cmp -s "$dir/crowd10.glb" "$dir/crowd10b.glb" || { echo "FAIL: crowd output differs between runs" >&2; status=1; }
grep -q '"walker-9/body"' "$dir/crowd10.glb" || { echo "FAIL: --count 10 has no walker-9" >&2; status=1; }
grep -q '"walker-1/body"' "$dir/crowd1.glb" && { echo "FAIL: --count 1 has a walker-1" >&2; status=1; }
# The extremes' transforms: a scaled, moved, re-lit scene with a new root node.
expect 0 street-canyon "$dir/scaled.glb" --unit-scale 1e-6 --origin 1e7,0,-1e7 --sun-elevation 90 --camera-near 0.01
grep -q '"unit-root"' "$dir/scaled.glb" || { echo "FAIL: no unit-root node" >&2; status=1; }
# Overwriting an existing file works (atomic rename), and leaves no temporary behind.
expect 0 street-canyon "$dir/canyon.glb"
leftovers=$(ls -A "$dir" | grep -c '\.tmp\.' || true)
[ "$leftovers" = 0 ] || { echo "FAIL: temporary files left behind" >&2; status=1; }

[ $status = 0 ] && echo "pnb-make-scene CLI: all checks passed"
exit $status
