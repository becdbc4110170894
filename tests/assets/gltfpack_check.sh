#!/bin/sh
# gltfpack_check.sh PNB_MAKE_SCENE GLTFPACK SCENE WORK_DIR
#
# Generates SCENE and has gltfpack (cgltf parse + cgltf_validate) load and re-pack it. Exit 77
# (ctest: skipped) if GLTFPACK is empty, i.e. gltfpack is not installed.
set -u
tool=${1:?usage: gltfpack_check.sh PNB_MAKE_SCENE GLTFPACK SCENE WORK_DIR}
gltfpack=${2-}
scene=${3:?}
dir=${4:?}
if [ -z "$gltfpack" ]; then
    echo "gltfpack not installed: skipped"
    exit 77
fi
mkdir -p "$dir"
"$tool" "$scene" "$dir/$scene.glb" || { echo "FAIL: pnb-make-scene $scene" >&2; exit 1; }
"$gltfpack" -i "$dir/$scene.glb" -o "$dir/$scene.packed.glb" -v >"$dir/$scene.log" 2>&1
code=$?
cat "$dir/$scene.log"
if [ $code != 0 ]; then
    echo "FAIL: gltfpack rejected $scene.glb (exit $code)" >&2
    exit 1
fi
# gltfpack reports loader problems as "Error"/"Warning" lines; none are expected.
if grep -qiE "^(error|warning)" "$dir/$scene.log"; then
    echo "FAIL: gltfpack complained about $scene.glb" >&2
    exit 1
fi
echo "gltfpack loaded $scene.glb"
