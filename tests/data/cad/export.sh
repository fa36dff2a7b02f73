#!/bin/sh
# Regenerates the binary STLs of the CAD test corpus from their OpenSCAD sources (committed, so
# the tests need no OpenSCAD: rendering all of them takes about 25 s with Debian's 2021.01).
# Usage: ./export.sh [name.scad ...]    Env: OPENSCAD (default: openscad on PATH)
# Reuses the examples' exporter: canonical triangle order, closedness and z = 0 checked.
set -eu
here="$(cd "$(dirname "$0")" && pwd)"
cd "$here"
OPENSCAD="${OPENSCAD:-openscad}"
[ "$#" -eq 0 ] && set -- *.scad
status=0
for src in "$@"; do
    name="$(basename "${src%.scad}")"
    if ! "$OPENSCAD" -o "$name.stl.tmp" --export-format binstl "$name.scad" >"$name.log" 2>&1; then
        echo "FAILED: $name.scad (see $name.log)" >&2
        rm -f "$name.stl.tmp"
        status=1
        continue
    fi
    mv "$name.stl.tmp" "$name.stl"
    rm -f "$name.log"
    python3 "$here/../../../examples/models/check_stl.py" --canonicalize "$name.stl" || status=1
done
exit $status
