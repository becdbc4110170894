#!/bin/sh
# check_format_deps.sh SOURCE_DIR [PNB_FORMAT_LINK_LIBRARIES]
#
# format/ depends on zstd and xxhash only: no GL, no windowing, no importers (docs/STYLE.md §2.3,
# ARCHITECTURE.md). Fails (exit 1) if
#   1. any file under format/ mentions a GL, windowing or importer library;
#   2. format/CMakeLists.txt links pnb_format to anything but zstd, xxhash and pnb_warnings, links
#      another format/ target to anything outside that set plus format's own libraries and the
#      header-only nlohmann-json (pnb_path_json: the camera-path keyframe file; build-only, so
#      nothing links it at run time) and pnb_cli (pnb-inspect's option table: the standard library
#      only, the floor below format/), or adds directory-wide link libraries;
#   3. PNB_FORMAT_LINK_LIBRARIES, the final LINK_LIBRARIES property of pnb_format as the build
#      generated it (';'-separated), names anything else. This catches a target_link_libraries
#      on pnb_format from outside format/CMakeLists.txt. Optional, so the script also runs on a
#      bare checkout.
set -u
set -f # library names are words, not globs

src=${1:?usage: check_format_deps.sh SOURCE_DIR [PNB_FORMAT_LINK_LIBRARIES]}
build_libs=${2:-}
cmake_file="$src/format/CMakeLists.txt"
status=0
fail() {
    echo "check_format_deps: $*" >&2
    status=1
}

# pnb_warnings may be wrapped in $<BUILD_INTERFACE:...> (kept out of the installed export).
allowed_format="PkgConfig::ZSTD PkgConfig::XXHASH pnb_warnings \$<BUILD_INTERFACE:pnb_warnings>"
allowed_other="$allowed_format pnb_format pnb::format pnb_inspect_lib pnb_cli \$<BUILD_INTERFACE:nlohmann_json::nlohmann_json>"

# 1. No mention of a forbidden library anywhere in format/.
hits=$(grep -rnE "epoxy|GL/|GLFW|assimp|tinygltf|draco|OpenImageIO" "$src/format/")
if [ -n "$hits" ]; then
    fail "format/ mentions a GL or importer dependency:"
    echo "$hits" >&2
fi

# 2. The link lines in format/CMakeLists.txt. Comments are dropped and the file is joined into
# one line so that calls spanning several lines are seen whole.
[ -f "$cmake_file" ] || fail "$cmake_file not found"
flat=$(sed 's/#.*//' "$cmake_file" | tr '\n\t' '  ')
if echo "$flat" | grep -qE '(^|[^_a-z])link_libraries[[:space:]]*\('; then
    fail "format/CMakeLists.txt uses directory-wide link_libraries()"
fi
calls=$(echo "$flat" | grep -oE 'target_link_libraries[[:space:]]*\([^)]*\)')
found_format=0
newline='
'
old_ifs=$IFS
IFS=$newline
for call in $calls; do
    IFS=$old_ifs
    # shellcheck disable=SC2046 # word splitting is the point
    set -- $(echo "$call" | sed 's/^target_link_libraries[[:space:]]*(//; s/)$//')
    target=$1
    shift
    if [ "$target" = pnb_format ]; then
        allowed=$allowed_format
        found_format=1
    else
        allowed=$allowed_other
    fi
    for lib in "$@"; do
        case "$lib" in PUBLIC | PRIVATE | INTERFACE) continue ;; esac
        case " $allowed " in
        *" $lib "*) ;;
        *) fail "format/CMakeLists.txt links $target to '$lib' (allowed: $allowed)" ;;
        esac
    done
done
IFS=$old_ifs
[ "$found_format" = 1 ] || fail "no target_link_libraries(pnb_format ...) in $cmake_file"

# 3. What the build actually links pnb_format to.
if [ -n "$build_libs" ]; then
    for lib in $(echo "$build_libs" | tr ';' ' '); do
        case " $allowed_format " in
        *" $lib "*) ;;
        *) fail "the build links pnb_format to '$lib' (allowed: $allowed_format)" ;;
        esac
    done
fi

[ "$status" = 0 ] && echo "check_format_deps: ok (pnb_format links only zstd, xxhash)"
exit $status
