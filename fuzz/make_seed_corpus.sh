#!/usr/bin/env bash
# Regenerates the committed seed corpus of container_reader_fuzz (fuzz/corpus/container_reader/).
# Run it after a format change, review the diff, commit the outputs.
#
#   fuzz/make_seed_corpus.sh [PNB_MAKE_SAMPLE]
#
# PNB_MAKE_SAMPLE defaults to the fuzz preset's build of pnb-make-sample (built if needed).
# Only the seed-* files are rewritten: regress-* files are inputs that once crashed the reader and
# stay as regression tests.
#
# The seeds are small box-room samples (the fuzzer's -max_len is 64 KiB, and small inputs mutate
# faster) plus damaged variants, so mutation starts from both sides of the accept/reject line.
set -euo pipefail
cd "$(dirname "$0")/.."

make_sample=${1:-}
if [ -z "$make_sample" ]; then
    cmake --preset asan >/dev/null
    cmake --build --preset asan --target pnb-make-sample >/dev/null
    make_sample=build/asan/assets_src/pnb-make-sample
fi

out=fuzz/corpus/container_reader
mkdir -p "$out"
rm -f "$out"/seed-*

"$make_sample" "$out/seed-valid-tex4.pnb" --texture-size 4 >/dev/null
"$make_sample" "$out/seed-valid-tex8-sub1.pnb" --texture-size 8 --subdivisions 1 >/dev/null
"$make_sample" "$out/seed-valid-tex1-sub2.pnb" --texture-size 1 --subdivisions 2 >/dev/null
"$make_sample" "$out/seed-valid-env.pnb" --texture-size 1 --environment >/dev/null

base=$out/seed-valid-tex4.pnb
size=$(stat -c %s "$base")

# Cut mid-file (inside some chunk) and cut exactly before the footer (a chunk-aligned end).
head -c $((size / 2)) "$base" >"$out/seed-truncated-half.pnb"
head -c $((size - 32)) "$base" >"$out/seed-truncated-no-footer.pnb"

# Extra bytes after the footer.
{ cat "$base"; printf 'trailing'; } >"$out/seed-trailing-bytes.pnb"

# One payload byte flipped in the middle of the file (bulk mesh/texture data): a checksum
# mismatch with checksums on, a decoder or validateScene input with them off.
cp "$base" "$out/seed-corrupt-payload.pnb"
mid=$((size / 2))
orig=$(od -An -tu1 -j "$mid" -N1 "$base" | tr -d ' ')
printf "$(printf '\\%03o' $(((orig ^ 0x5A) & 0xFF)))" |
    dd of="$out/seed-corrupt-payload.pnb" bs=1 seek="$mid" conv=notrunc status=none

# Header only: the smallest input that passes the file header checks.
head -c 64 "$base" >"$out/seed-header-only.pnb"

ls -l "$out"
