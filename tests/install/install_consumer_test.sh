#!/usr/bin/env bash
# install_consumer_test.sh BUILD_DIR CONSUMER_SOURCE_DIR CMAKE CXX_COMPILER
#
# Installs BUILD_DIR into a temporary prefix (cmake --install), then configures and builds
# tests/install/consumer against it as a separate project: find_package(Penumbra), a scene
# converted by the installed pnb-convert as a build step (pnb_add_scene), read back with the
# installed pnb::format; pnb::player linked. Checks that the package came from the prefix (not
# the build tree), the scene's contents, and that installed tools run from another directory.
# The temporary directory is removed on exit.
set -euo pipefail
build=${1:?usage: install_consumer_test.sh BUILD_DIR CONSUMER_SOURCE_DIR CMAKE CXX_COMPILER}
consumer_src=${2:?}
cmake=${3:?}
cxx=${4:?}

tmp=$(mktemp -d "${TMPDIR:-/tmp}/pnb_install_test.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix
fail() {
    echo "install_consumer_test: FAIL: $*" >&2
    exit 1
}

"$cmake" --install "$build" --prefix "$prefix" >"$tmp/install.log" || {
    cat "$tmp/install.log" >&2
    fail "cmake --install"
}
config=$(find "$prefix" -path '*/cmake/Penumbra/PenumbraConfig.cmake')
[ -n "$config" ] || fail "no PenumbraConfig.cmake under the prefix"
for f in bin/pnb-convert bin/pnb-play bin/pnb-edit bin/pnb-inspect bin/pnb-reference bin/pnb-flip \
    bin/pnb-make-scene bin/pnb-make-sample bin/pnb-sweep include/pnb/reader.h include/pnb_player/renderer.h \
    share/doc/penumbra/README.md share/doc/penumbra/docs/FORMAT.md share/penumbra/plot_frames.py; do
    [ -e "$prefix/$f" ] || fail "$f not installed"
done
codec=$(find "$prefix" -path '*/penumbra/libpnb_image_oiio.so')
[ -n "$codec" ] || fail "the image codec module libpnb_image_oiio.so is not installed"
# The installed converter loads its image codec from the prefix, not from the build tree (it
# would find that one last): a quad textured with a TGA (PNG and JPEG need no module), with the
# dynamic loader reporting what it loads.
textured=$tmp/quad.obj
printf 'mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl m\nf 1/1 2/2 3/3\n' \
    >"$textured"
printf 'newmtl m\nKd 1 1 1\nmap_Kd tiles.tga\n' >"$tmp/quad.mtl"
# An 18-byte header (uncompressed true-colour, 1 x 1, 24 bits) and one BGR texel.
printf '\0\0\2\0\0\0\0\0\0\0\0\0\1\0\1\0\30\0\100\200\300' >"$tmp/tiles.tga"
LD_DEBUG=files "$prefix/bin/pnb-convert" "$textured" -o "$tmp/textured.pnb" -q \
    >"$tmp/codec.log" 2>&1 || { cat "$tmp/codec.log" >&2; fail "installed pnb-convert on $textured"; }
grep -q "file=$codec .*dynamically loaded" "$tmp/codec.log" ||
    fail "the installed pnb-convert did not load $codec: $(grep libpnb_image_oiio "$tmp/codec.log")"

# The consumer, configured from a directory outside the source and build trees. The package
# registries are off, so only CMAKE_PREFIX_PATH (or the system) can provide Penumbra.
cd "$tmp"
"$cmake" -S "$consumer_src" -B "$tmp/consumer" -G Ninja -DCMAKE_CXX_COMPILER="$cxx" \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF \
    >"$tmp/configure.log" 2>&1 || {
    cat "$tmp/configure.log" >&2
    fail "configuring the consumer"
}
penumbra_dir=$(sed -n 's/^Penumbra_DIR:PATH=//p' "$tmp/consumer/CMakeCache.txt")
[ "$penumbra_dir" = "$(dirname "$config")" ] ||
    fail "Penumbra_DIR is '$penumbra_dir', not the prefix's $(dirname "$config")"

"$cmake" --build "$tmp/consumer" >"$tmp/build.log" 2>&1 || {
    cat "$tmp/build.log" >&2
    fail "building the consumer"
}
convert=$(cat "$tmp/consumer/pnb_convert_location.txt")
[ "$convert" = "$prefix/bin/pnb-convert" ] ||
    fail "pnb_add_scene ran '$convert', not the installed one"
grep -q "Converting .*two_boxes.obj" "$tmp/build.log" ||
    fail "the scene was not converted as a build step"

scene=$tmp/consumer/two_boxes.pnb
out=$("$tmp/consumer/read_scene" "$scene") || fail "read_scene failed: $out"
echo "$out"
# Two boxes, two materials, 12 triangles each. The chunk count follows the shader library, so it
# is compared with what the installed pnb-inspect reports for the same file.
expected=$'meshes=2\nmaterials=2\ntriangles=24'
[ "$(echo "$out" | grep -v '^chunks=')" = "$expected" ] || fail "read_scene printed:
$out
expected (besides chunks=):
$expected"
chunks=$(echo "$out" | sed -n 's/^chunks=//p')
inspect=$("$prefix/bin/pnb-inspect" "$scene") || fail "installed pnb-inspect failed"
inspected=$(echo "$inspect" | sed -n 's/^format: .* \([0-9]*\) chunks + table of contents$/\1/p')
if [ -z "$chunks" ] || [ "$chunks" != "$inspected" ]; then
    fail "read_scene counted '$chunks' chunks, pnb-inspect '$inspected'"
fi

png=$("$tmp/consumer/write_png" "$tmp/out.png") || fail "write_png failed: $png"
[ "$(head -c 8 "$tmp/out.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ||
    fail "write_png did not write a PNG"

# Installed tools work from any directory (nothing read relative to the source tree).
"$prefix/bin/pnb-inspect" --verify "$scene" >/dev/null || fail "installed pnb-inspect --verify"
"$prefix/bin/pnb-play" --help >/dev/null || fail "installed pnb-play --help"
# pnb-play's benchmark plot script is embedded (it used to be read from the source tree).
"$prefix/bin/pnb-play" "$scene" --headless --bench --frames 3 --fixed-dt --size 64x36 \
    --out "$tmp/bench" >"$tmp/play.log" 2>&1 || {
    cat "$tmp/play.log" >&2
    fail "installed pnb-play --headless --bench"
}
[ -f "$tmp/bench/summary.json" ] || fail "pnb-play wrote no summary.json"
if "${PNB_PYTHON:-/usr/bin/python3}" -c 'import matplotlib' 2>/dev/null; then
    [ -f "$tmp/bench/frame_times.png" ] || {
        cat "$tmp/play.log" >&2
        fail "installed pnb-play wrote no frame_times.png"
    }
fi
[ ! -e "$tmp/bench/.plot_frames.py" ] || fail "pnb-play left its plot script behind"

# pnb-sweep, installed: runs a sweep with the prefix's tools (not the build tree's) from here.
printf 'name = "installed"\nframes = 2\nsize = "64x36"\n[axes]\n"shadows.technique" = ["off", "pssm"]\n[[scenes]]\nsource = "%s"\n' \
    "$scene" >"$tmp/sweep.toml"
PNB_PYTHON=${PNB_PYTHON:-/usr/bin/python3} "$prefix/bin/pnb-sweep" plan "$tmp/sweep.toml" \
    --results "$tmp/sweep" -o "$tmp/plan.json" >"$tmp/sweep.log" 2>&1 || {
    cat "$tmp/sweep.log" >&2
    fail "installed pnb-sweep plan"
}
grep -q "\"play\": \"$prefix/bin/pnb-play\"" "$tmp/plan.json" || fail "pnb-sweep does not use the installed pnb-play"
PNB_PYTHON=${PNB_PYTHON:-/usr/bin/python3} "$prefix/bin/pnb-sweep" run --local "$tmp/sweep.toml" \
    --results "$tmp/sweep" >>"$tmp/sweep.log" 2>&1 || {
    cat "$tmp/sweep.log" >&2
    fail "installed pnb-sweep run --local"
}
[ "$(ls "$tmp"/sweep/*/job.json | wc -l)" = 2 ] || fail "pnb-sweep did not finish its 2 jobs"

echo "install_consumer_test: ok (installed to a temporary prefix, consumer built and ran)"
