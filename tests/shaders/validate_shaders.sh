#!/usr/bin/env bash
# Every real shader through glslangValidator as GLSL 4.50 core (the #version line each carries),
# expanded as at run time by pnb-expand-shaders: every program the converter can pack, in every
# permutation, and every program the player builds from player/shaders. Fails naming each program
# that does not compile or link, with glslang's messages.
#   compile  every distinct stage text of every program, each compiled and linked on its own
#            (many files per glslangValidator: one process per file would spend ~60 ms of its
#            start-up parsing the built-in symbols, ~5 min for the ~4600 programs);
#   link     stages linked together (-l) for every player program and, per scene program, once
#            for each distinct vertex stage (with the first fragment variant that pairs with it):
#            the fragment variants of a program differ inside functions, not in their in/out
#            declarations, which stand outside any #if. PNB_SHADERS_LINK_ALL=1 links every
#            program instead (~5 min).
# Usage: validate_shaders.sh PNB_EXPAND_SHADERS GLSLANG_VALIDATOR
set -euo pipefail
expand=$1 glslang=$2
jobs=${PNB_SHADER_JOBS:-2}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$expand" "$tmp/out" || fail "pnb-expand-shaders could not expand the shaders"
programs=$tmp/out/programs.tsv
[ -s "$programs" ] || fail "pnb-expand-shaders wrote no programs"

# Labels of the programs that use any stage file listed in $1 (one path a line).
programs_using() {
    awk -F'\t' 'NR == FNR { bad[$0] = 1; next }
        { n = split($2, s, " "); for (i = 1; i <= n; ++i) if (s[i] in bad) { print "  " $1; break } }' \
        "$1" "$programs"
}

# --- compile: the stage files in $jobs batches, run at once, each with its own log.
find "$tmp/out/stages" -type f | sort >"$tmp/stages"
split -n "l/$jobs" "$tmp/stages" "$tmp/batch."
pids=()
for batch in "$tmp"/batch.*; do
    xargs -a "$batch" "$glslang" >"$batch.log" 2>&1 &
    pids+=($!)
done
compile_status=0
for pid in "${pids[@]}"; do wait "$pid" || compile_status=1; done
# glslangValidator prints each file's name, then its ERROR lines: the failing files.
cat "$tmp"/batch.*.log | awk -v dir="$tmp/out/stages/" 'index($0, dir) == 1 { file = $0; next }
    /^ERROR/ && file != "" { print file; file = "" }' >"$tmp/failed-stages"
if [ -s "$tmp/failed-stages" ] || [ "$compile_status" != 0 ]; then
    # The first few failing stages with their messages; `N:L` in a message is line L of file N
    # in the stage's `// pnb-files:` table (file 0 is the stage itself).
    cat "$tmp"/batch.*.log | awk -v dir="$tmp/out/stages/" 'index($0, dir) == 1 { file = $0; next }
        /^ERROR/ && file != "" && shown < 8 { if (file != last) { ++shown; print "--- " file; last = file
            while ((getline line < file) > 0) if (line ~ /^\/\/ pnb-files:/) { print line; break }
            close(file) } print }' >&2
    [ -s "$tmp/failed-stages" ] || cat "$tmp"/batch.*.log >&2
    echo "programs with a stage that does not compile:" >&2
    programs_using "$tmp/failed-stages" >&2
    fail "$(sort -u "$tmp/failed-stages" | wc -l) stage text(s) do not compile (exit $compile_status)"
fi
echo "compile: $(wc -l <"$tmp/stages") stage texts of $(wc -l <"$programs") programs: ok"

# --- link: multi-stage programs, as the header says.
if [ "${PNB_SHADERS_LINK_ALL:-0}" = 1 ]; then
    awk -F'\t' 'split($2, s, " ") > 1 { print $2 }' "$programs" >"$tmp/links"
else
    awk -F'\t' 'split($2, s, " ") > 1 { name = $1; sub(/\[.*/, "", name)
        if (!((name, s[1]) in seen)) { seen[name, s[1]] = 1; print $2 } }' "$programs" >"$tmp/links"
fi
[ -s "$tmp/links" ] || fail "no multi-stage program to link"
# One glslangValidator per program; a failing one appends its stage files to link-failed.
: >"$tmp/link-failed"
xargs -a "$tmp/links" -P "$jobs" -L 1 sh -c \
    'out=$("$0" -l "$@" 2>&1) || { printf "%s\n" "$out" >&2; printf "%s\n" "$*" >>"'"$tmp/link-failed"'"; }' \
    "$glslang"
if [ -s "$tmp/link-failed" ]; then
    echo "programs that do not link:" >&2
    awk -F'\t' 'NR == FNR { bad[$0] = 1; next } $2 in bad { print "  " $1 }' "$tmp/link-failed" "$programs" >&2
    fail "$(wc -l <"$tmp/link-failed") program(s) do not link"
fi
echo "link: $(wc -l <"$tmp/links") programs: ok"
