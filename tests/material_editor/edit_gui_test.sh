#!/usr/bin/env bash
# pnb-edit's window under Xvfb, driven through the same actions the widgets call (--ui-set,
# --ui-save-as): move the translucent pane of box-room into its own deferred layer, save, verify
# the file with pnb-inspect, read the change back with --list, play the result with pnb-play,
# and check the window screenshot is not blank.
# Usage: edit_gui_test.sh PNB_EDIT PNB_INSPECT PNB_PLAY SCENE.pnb
set -euo pipefail
edit=$1 inspect=$2 play=$3 scene=$4
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
command -v xvfb-run >/dev/null || { echo "xvfb-run missing (scripts/setup installs it)"; exit 1; }

cp "$scene" "$tmp/in.pnb"
before=$(sha256sum "$tmp/in.pnb" | cut -d' ' -f1)
xvfb-run -a -s "-screen 0 1400x800x24" "$edit" "$tmp/in.pnb" \
    --ui-set 'tinted-glass.shading_path=deferred' --ui-set 'tinted-glass.layer_priority=2' \
    --ui-save-as "$tmp/out.pnb" --ui-frames 8 --ui-screenshot "$tmp/window.png" \
    || fail "pnb-edit GUI session failed"
[ "$(sha256sum "$tmp/in.pnb" | cut -d' ' -f1)" = "$before" ] || fail "the opened file changed (Save As)"
"$inspect" "$tmp/out.pnb" --verify >/dev/null || fail "saved file does not verify"
"$edit" "$tmp/out.pnb" --list >"$tmp/list.txt"
# The material's block is taken into a variable, not piped: under pipefail a `grep -A12 | grep -q`
# fails when the first grep dies of SIGPIPE after the second has matched.
glass=$(grep -A12 "'tinted-glass'" "$tmp/list.txt") || fail "no material 'tinted-glass' in --list"
grep -q "shading_path *= deferred" <<<"$glass" || fail "path not saved"
grep -q "layer_priority *= 2" <<<"$glass" || fail "layer not saved"
"$play" "$tmp/out.pnb" --headless -q --screenshot "$tmp/played.png" || fail "pnb-play cannot play the result"
# Not blank: the window shows panels and the viewport, so its pixels vary.
/usr/bin/python3 - "$tmp/window.png" <<'PY' || fail "window screenshot is blank"
import sys
import matplotlib.image as mi
img = mi.imread(sys.argv[1])
assert img.shape[0] >= 400 and img.shape[1] >= 800, img.shape
assert img[..., :3].std() > 0.05, img[..., :3].std()
PY
# Every property label shows whole at the size the issue names (1280x800) and at the default:
# pnb-edit measures each widget's label against the panel's edge (--ui-check-labels, exit 4).
for size in 1280x800 1400x800; do
    xvfb-run -a -s "-screen 0 1400x800x24" "$edit" "$tmp/in.pnb" --ui-set 'tinted-glass.layer_priority=0' \
        --ui-size "$size" --ui-frames 4 --ui-check-labels >"$tmp/labels.txt" 2>&1 \
        || { cat "$tmp/labels.txt" >&2; fail "property labels cut off at $size"; }
    grep -q "shown whole at" "$tmp/labels.txt" || fail "no label check ran at $size"
done

# Another program saves the open file (issue 44). --ui-external runs it at frame 3; the window
# notices at frame 4; --ui-on-change answers its prompt; --ui-save saves in place at frame 5.
field() { # FILE MATERIAL FIELD -> the value as --list prints it
    "$edit" "$1" --list | awk -v m="'$2'" -v f="$3" '$1=="material" && $3==m {on=1; next}
        $1=="material" {on=0} on && $1==f {print $3}'
}
window() { # SCENE ARGS...: a scripted window session, its output in $tmp/window.log
    local scene=$1; shift
    xvfb-run -a -s "-screen 0 1400x800x24" "$edit" "$scene" --ui-frames 8 "$@" >"$tmp/window.log" 2>&1
}
cp "$scene" "$tmp/disk.pnb"
window "$tmp/disk.pnb" --ui-set 'white-wall.roughness=0.25' \
    --ui-external "'$edit' '$tmp/disk.pnb' -q --set red-wall.metallic=0.75" --ui-on-change merge --ui-save \
    || { cat "$tmp/window.log" >&2; fail "merge session failed"; }
grep -q "their changes: 'red-wall'.metallic: 0 -> 0.75" "$tmp/window.log" || { cat "$tmp/window.log" >&2; fail "the other change is not named"; }
[ "$(field "$tmp/disk.pnb" white-wall roughness)" = 0.25 ] || fail "merge: the window's edit is lost"
[ "$(field "$tmp/disk.pnb" red-wall metallic)" = 0.75 ] || fail "merge: the other program's edit is lost"

# Both change one field: Merge refuses naming it, the save in place refuses, their file stays.
cp "$scene" "$tmp/disk.pnb"
if window "$tmp/disk.pnb" --ui-set 'red-wall.metallic=0.25' \
    --ui-external "'$edit' '$tmp/disk.pnb' -q --set red-wall.metallic=0.75" --ui-on-change merge --ui-save; then
    cat "$tmp/window.log" >&2; fail "a conflicting merge and save went through"
fi
grep -q "'red-wall'.metallic: mine 0.25, theirs 0.75" "$tmp/window.log" || { cat "$tmp/window.log" >&2; fail "the conflict is not named"; }
grep -q "changed-on-disk" "$tmp/window.log" || fail "the save did not refuse"
[ "$(field "$tmp/disk.pnb" red-wall metallic)" = 0.75 ] || fail "the refused save replaced their file"

# The explicit choice: mine win on the conflict, their other edit kept.
cp "$scene" "$tmp/disk.pnb"
window "$tmp/disk.pnb" --ui-set 'red-wall.metallic=0.25' \
    --ui-external "'$edit' '$tmp/disk.pnb' -q --set red-wall.metallic=0.75 --set green-wall.roughness=0.5" \
    --ui-on-change merge-mine --ui-save || { cat "$tmp/window.log" >&2; fail "merge-mine session failed"; }
[ "$(field "$tmp/disk.pnb" red-wall metallic)" = 0.25 ] || fail "merge-mine: mine did not win"
[ "$(field "$tmp/disk.pnb" green-wall roughness)" = 0.5 ] || fail "merge-mine: their other edit is lost"

# No unsaved edits: the window reloads on its own and says what changed.
cp "$scene" "$tmp/disk.pnb"
window "$tmp/disk.pnb" --ui-external "'$edit' '$tmp/disk.pnb' -q --set red-wall.metallic=0.75" \
    || { cat "$tmp/window.log" >&2; fail "reload session failed"; }
grep -q "status: reloaded: .*'red-wall'.metallic: 0 -> 0.75" "$tmp/window.log" || { cat "$tmp/window.log" >&2; fail "no reload"; }
echo "pnb-edit GUI: ok"
