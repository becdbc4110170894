#!/bin/sh
# pnb-edit batch mode end to end: exit codes, in-place and -o saves that pnb-inspect verifies,
# deterministic output, JSON that parses, and a file left untouched by every failure.
# usage: edit_cli_test.sh PNB_EDIT PNB_INSPECT SCENE.pnb WORKDIR
set -u
EDIT=$1 INSPECT=$2 SCENE=$3 WORK=$4
rm -rf "$WORK" && mkdir -p "$WORK" || exit 1
fail=0
check() { # check NAME EXPECTED_RC ACTUAL_RC
    if [ "$2" != "$3" ]; then echo "FAIL: $1: exit $3, expected $2"; fail=1; else echo "ok: $1"; fi
}
same() { # same NAME A B
    if cmp -s "$2" "$3"; then echo "ok: $1"; else echo "FAIL: $1: $2 and $3 differ"; fail=1; fi
}

cp "$SCENE" "$WORK/scene.pnb"
cp "$SCENE" "$WORK/original.pnb"

"$EDIT" --help > "$WORK/help.txt"; check "--help" 0 $?
grep -q "emissive_texture" "$WORK/help.txt" || { echo "FAIL: --help lists no fields"; fail=1; }
grep -q "Exit codes" "$WORK/help.txt" || { echo "FAIL: --help lists no exit codes"; fail=1; }

"$EDIT" "$WORK/scene.pnb" --list > "$WORK/list.txt"; check "--list" 0 $?
same "--list does not write" "$WORK/scene.pnb" "$WORK/original.pnb"
if command -v python3 > /dev/null; then
    "$EDIT" "$WORK/scene.pnb" --list --json > "$WORK/list.json"; check "--list --json" 0 $?
    python3 -m json.tool "$WORK/list.json" > /dev/null; check "JSON parses" 0 $?
fi

# Failures: usage (1), bad input (2), unwritable output (4); never a changed file.
"$EDIT" "$WORK/scene.pnb" --set 'nothing.roughness=0.5' 2> "$WORK/err1.txt"; check "unknown material" 2 $?
grep -q "materials: " "$WORK/err1.txt" || { echo "FAIL: no material list in: $(cat "$WORK/err1.txt")"; fail=1; }
"$EDIT" "$WORK/scene.pnb" --set '*.shininess=3' 2> "$WORK/err2.txt"; check "unknown field" 2 $?
grep -q "fields: .*roughness" "$WORK/err2.txt" || { echo "FAIL: no field list in: $(cat "$WORK/err2.txt")"; fail=1; }
"$EDIT" "$WORK/scene.pnb" --set '*.roughness=high' 2> /dev/null; check "bad value" 2 $?
"$EDIT" "$WORK/scene.pnb" --set 'no-dot-here' 2> /dev/null; check "malformed --set" 1 $?
"$EDIT" "$WORK/scene.pnb" --bogus 2> /dev/null; check "unknown option" 1 $?
"$EDIT" "$WORK/scene.pnb" --set '*.roughness=0.5' -o "$WORK/no/such/dir/out.pnb" 2> /dev/null
check "unwritable output" 4 $?
"$EDIT" "$WORK/missing.pnb" --list 2> /dev/null; check "missing scene" 2 $?
same "failures leave the file untouched" "$WORK/scene.pnb" "$WORK/original.pnb"
[ "$(ls -A "$WORK" | grep -c '\.tmp\.')" = 0 ] || { echo "FAIL: temporaries left: $(ls -A "$WORK")"; fail=1; }

# A no-op edit does not rewrite the file.
"$EDIT" "$WORK/scene.pnb" --set '*.layer_priority=0' > "$WORK/noop.txt"; check "no-op edit" 0 $?
grep -q "no change" "$WORK/noop.txt" || { echo "FAIL: no 'no change' note: $(cat "$WORK/noop.txt")"; fail=1; }
same "no-op edit leaves the file" "$WORK/scene.pnb" "$WORK/original.pnb"

# An edit the player cannot show is applied but named (alpha_cutoff outside mask mode).
"$EDIT" "$WORK/scene.pnb" --set '*.alpha_cutoff=0.25' -o "$WORK/cutoff.pnb" 2> "$WORK/note.txt" >/dev/null
check "edit without effect" 0 $?
grep -q "note: alpha_cutoff has no effect on .* alpha_mode mask only" "$WORK/note.txt" ||
    { echo "FAIL: no note for an edit without effect: $(cat "$WORK/note.txt")"; fail=1; }

# Edits: deterministic (-o twice gives the same bytes), in place == -o, and valid.
"$EDIT" "$WORK/scene.pnb" --set '*.shading_path=forward' --set '*.roughness=0.25' -o "$WORK/a.pnb" > "$WORK/a.txt"
check "edit -o a" 0 $?
grep -q "saved .*bytes in .* s" "$WORK/a.txt" || { echo "FAIL: no save time: $(cat "$WORK/a.txt")"; fail=1; }
"$EDIT" "$WORK/scene.pnb" --set '*.shading_path=forward' --set '*.roughness=0.25' -o "$WORK/b.pnb" -q > "$WORK/b.txt"
check "edit -o b" 0 $?
[ -s "$WORK/b.txt" ] && { echo "FAIL: -q printed: $(cat "$WORK/b.txt")"; fail=1; }
same "deterministic" "$WORK/a.pnb" "$WORK/b.pnb"
same "-o leaves the input" "$WORK/scene.pnb" "$WORK/original.pnb"
"$EDIT" "$WORK/scene.pnb" --set '*.shading_path=forward' --set '*.roughness=0.25' -q; check "edit in place" 0 $?
same "in place == -o" "$WORK/scene.pnb" "$WORK/a.pnb"
"$INSPECT" --verify "$WORK/scene.pnb"; check "pnb-inspect --verify" 0 $?

exit $fail
