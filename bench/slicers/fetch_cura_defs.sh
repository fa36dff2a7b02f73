#!/usr/bin/env bash
# Obtain the Cura 4.13 machine definition files (fdmprinter.def.json, fdmextruder.def.json).
# They are not in the `cura-engine` package but in the Debian package `cura` (the GUI) of the
# same version; we download the .deb and unpack it with dpkg -x, without installing the GUI.
#
# Idempotent: if the files are already in the cache dir nothing is downloaded.
# Cache dir: $CURA_DEFS_DIR, else ${XDG_CACHE_HOME:-$HOME/.cache}/clever-support/cura-defs
# Prints the directory that holds the two .def.json files (last line of stdout).
set -euo pipefail

DIR="${CURA_DEFS_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/clever-support/cura-defs}"
FILES=(fdmprinter.def.json fdmextruder.def.json)

have_all() {
  local f
  for f in "${FILES[@]}"; do [[ -s "$DIR/$f" ]] || return 1; done
  return 0
}

if ! have_all; then
  mkdir -p "$DIR"
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
  # apt-get download writes to the current directory; it runs unprivileged-ok as root or user.
  if ! (cd "$tmp" && apt-get download cura >/dev/null 2>"$tmp/err.log"); then
    echo "apt-get download cura failed; running apt-get update and retrying" >&2
    if [[ $(id -u) -eq 0 ]]; then apt-get update >/dev/null 2>&1 || true
    else sudo -n apt-get update >/dev/null 2>&1 || true; fi
    (cd "$tmp" && apt-get download cura >/dev/null) || {
      cat "$tmp/err.log" >&2; echo "error: could not download the Debian package 'cura'" >&2; exit 1; }
  fi
  deb="$(ls "$tmp"/cura_*.deb | head -n1)"
  ver="$(dpkg-deb -f "$deb" Version)"
  case "$ver" in
    4.13.*) ;;
    *) echo "warning: package cura is version $ver, expected 4.13.x (CuraEngine is 4.13)" >&2 ;;
  esac
  dpkg -x "$deb" "$tmp/x"
  for f in "${FILES[@]}"; do
    src="$(find "$tmp/x" -name "$f" -path '*definitions*' | head -n1)"
    [[ -n "$src" ]] || { echo "error: $f not found in $deb" >&2; exit 1; }
    cp "$src" "$DIR/$f.part" && mv "$DIR/$f.part" "$DIR/$f"
  done
  echo "$ver" > "$DIR/VERSION"
fi

have_all || { echo "error: definitions missing in $DIR" >&2; exit 1; }
echo "$DIR"
