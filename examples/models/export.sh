#!/bin/sh
# Regenerate the binary STLs of the clever-support example models from their
# OpenSCAD sources and sanity-check them with check_stl.py.
#
# Usage: ./export.sh [name ...]      (default: every *.scad in this folder)
# Env:   OPENSCAD=/path/to/openscad  (default: openscad on PATH;
#        tested with OpenSCAD 2021.01 from Debian)
#        EXPORT_DIR=dir              (default: this folder; bench/validation/export.sh uses it)
#
# Idempotent: every run overwrites <name>.stl.  CGAL emits the triangles in
# a run-dependent order, so check_stl.py --canonicalize sorts them; the
# resulting files are byte-identical from run to run.
set -eu

here="$(cd "$(dirname "$0")" && pwd)"
cd "${EXPORT_DIR:-$here}"
OPENSCAD="${OPENSCAD:-openscad}"

if [ "$#" -eq 0 ]; then
    set -- *.scad
fi

status=0
for src in "$@"; do
    name="${src%.scad}"
    name="$(basename "$name")"
    out="$name.stl"
    tmp="$name.stl.tmp"
    start=$(date +%s)
    # render (CGAL) and export as binary STL
    if ! "$OPENSCAD" -o "$tmp" --export-format binstl "$name.scad" \
            >"$name.log" 2>&1; then
        echo "FAILED: $name.scad (see $name.log)" >&2
        rm -f "$tmp"
        status=1
        continue
    fi
    end=$(date +%s)
    mv "$tmp" "$out"
    rm -f "$name.log"
    echo "== $name: rendered in $((end - start)) s"
    # canonical triangle order (CGAL's varies run to run), then check
    python3 "$here/check_stl.py" --canonicalize "$out" || status=1
done
exit $status
