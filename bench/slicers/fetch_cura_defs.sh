#!/usr/bin/env bash
# Unpack Cura 4.13 (the GUI's Python code, machine definitions, qualities, variants, materials) into a
# cache folder, without installing the GUI. CuraEngine (Debian `cura-engine`) has no definitions:
# they are in the Debian package `cura` of the same version. We `apt-get download` it together with
# `python3-uranium` (the Uranium framework Cura's code runs on) and `fdm-materials` (the materials
# Cura's quality lookup needs) and unpack the three with `dpkg -x`. scripts/install-deps.sh runs
# this once; the tests only look (--no-fetch), so a test run never downloads.
#
# Idempotent: when the cache is complete nothing is downloaded.
# Cache: $CURA_413_DIR, else ${XDG_CACHE_HOME:-$HOME/.cache}/clever-support/cura-4.13
#   usr/share/cura/resources/{definitions,extruders,quality,variants,materials}
#   usr/lib/python3/dist-packages/{cura,UM}, usr/lib/cura/plugins
# Prints the definitions folder (last line of stdout), or with --root the cache folder.
# $CURA_DEFS_DIR, if set, names a definitions folder to use as it is (bench/slicers/README.md).
# --no-fetch: exit 1 with a message instead of downloading when the cache is incomplete.
set -euo pipefail

fetch=1 print_root=0
for arg in "$@"; do
  case "$arg" in
    --no-fetch) fetch=0 ;;
    --root) print_root=1 ;;
    *) echo "usage: fetch_cura_defs.sh [--no-fetch] [--root]" >&2; exit 2 ;;
  esac
done

ROOT="${CURA_413_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/clever-support/cura-4.13}"
RES="$ROOT/usr/share/cura/resources"
PACKAGES=(cura python3-uranium fdm-materials)
# Files from each package: the cache is complete when they are there (it is renamed into place
# only after every package was unpacked).
NEEDED=("$RES/definitions/fdmprinter.def.json" "$RES/definitions/creality_ender3.def.json"
        "$RES/definitions/fdmextruder.def.json" "$ROOT/usr/lib/python3/dist-packages/cura/Machines/MachineNode.py"
        "$ROOT/usr/lib/python3/dist-packages/UM/Settings/ContainerRegistry.py" "$RES/materials/generic_pla.xml.fdm_material")

have_all() {
  local f
  for f in "${NEEDED[@]}"; do [[ -s "$f" ]] || return 1; done
  return 0
}

say() { if [[ $print_root == 1 ]]; then echo "$ROOT"; else echo "${CURA_DEFS_DIR:-$RES/definitions}"; fi; }

if [[ -n "${CURA_DEFS_DIR:-}" && $print_root == 0 ]]; then say; exit 0; fi
if have_all; then say; exit 0; fi
if [[ $fetch == 0 ]]; then
  echo "Cura 4.13's definitions are not unpacked in $ROOT (scripts/install-deps.sh or bench/slicers/fetch_cura_defs.sh does it)" >&2
  exit 1
fi

mkdir -p "$(dirname "$ROOT")"
tmp="$(mktemp -d "$(dirname "$ROOT")/cura-4.13.part.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
# apt-get download writes to the current directory, as root or as a user.
if ! (cd "$tmp" && apt-get download "${PACKAGES[@]}" >/dev/null 2>"$tmp/err.log"); then
  echo "apt-get download ${PACKAGES[*]} failed; running apt-get update and retrying" >&2
  if [[ $(id -u) -eq 0 ]]; then apt-get update >/dev/null 2>&1 || true
  else sudo -n apt-get update >/dev/null 2>&1 || true; fi
  (cd "$tmp" && apt-get download "${PACKAGES[@]}" >/dev/null 2>"$tmp/err.log") || {
    cat "$tmp/err.log" >&2; echo "error: could not download the Debian packages ${PACKAGES[*]}" >&2; exit 1; }
fi
ver="$(dpkg-deb -f "$(ls "$tmp"/cura_*.deb | head -n1)" Version)"
case "$ver" in
  4.13.*) ;;
  *) echo "warning: package cura is version $ver, expected 4.13.x (CuraEngine is 4.13)" >&2 ;;
esac
for deb in "$tmp"/*.deb; do
  dpkg -x "$deb" "$tmp/x"
done
echo "$ver" > "$tmp/x/VERSION"
# Into place in one rename, so an interrupted run never leaves a cache that looks complete.
rm -rf "$ROOT"
mv "$tmp/x" "$ROOT"
have_all || { echo "error: Cura's files are missing in $ROOT after unpacking" >&2; exit 1; }
say
