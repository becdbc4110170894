#!/usr/bin/env bash
# deb_package_test.sh BUILD_DIR CPACK
#
# Builds the Debian package with CPack (into a temporary directory, removed on exit) and checks
# it: named penumbra, Depends holds both the shared libraries' packages (dpkg-shlibdeps) and the
# -dev packages PenumbraConfig.cmake's find_dependency() calls need, and it contains the tools
# and the CMake package.
set -euo pipefail
build=${1:?usage: deb_package_test.sh BUILD_DIR CPACK}
cpack=${2:?}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/pnb_deb_test.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() {
    echo "deb_package_test: FAIL: $*" >&2
    exit 1
}

(cd "$build" && "$cpack" -G DEB -B "$tmp") >"$tmp/cpack.log" 2>&1 || {
    cat "$tmp/cpack.log" >&2
    fail "cpack -G DEB"
}
deb=$(find "$tmp" -maxdepth 1 -name 'penumbra_*.deb')
[ -n "$deb" ] || fail "no penumbra_*.deb written"
echo "$(basename "$deb"): $(du -h "$deb" | cut -f1)"

info=$(dpkg-deb -I "$deb")
echo "$info" | grep -E '^ (Package|Version|Depends):'
[ "$(dpkg-deb -f "$deb" Package)" = penumbra ] || fail "package name is not penumbra"
depends=$(dpkg-deb -f "$deb" Depends)
names=$(echo "$depends" | tr ',|' '\n' | sed 's/^ *//; s/[ (].*//')
# From dpkg-shlibdeps: the C++ runtime every tool loads, and two of the libraries they use;
# libegl1 (dlopened by epoxy) by hand; the -dev packages of the exported link interfaces, for
# find_package(Penumbra).
# libopenimageio2.4 comes from the image codec module pnb-convert loads on demand; python3 runs
# pnb-sweep.
for pkg in libstdc++6 libzstd1 libassimp5 libopenimageio2.4 libegl1 libzstd-dev libxxhash-dev libepoxy-dev \
    libglfw3-dev libglm-dev nlohmann-json3-dev zlib1g-dev python3; do
    grep -qxF "$pkg" <<<"$names" || fail "Depends lacks $pkg: $depends"
done

contents=$(dpkg-deb -c "$deb")
for f in ./usr/bin/pnb-convert ./usr/bin/pnb-play ./usr/lib/cmake/Penumbra/PenumbraConfig.cmake \
    ./usr/lib/cmake/Penumbra/PnbAddScene.cmake ./usr/include/pnb/reader.h \
    ./usr/share/doc/penumbra/README.md ./usr/lib/penumbra/libpnb_image_oiio.so ./usr/bin/pnb-sweep \
    ./usr/share/penumbra/sweep/pnb_sweep.py; do
    grep -qE " $f\$" <<<"$contents" || fail "the package lacks $f"
done
echo "deb_package_test: ok"
