#!/bin/sh
# Regenerate the binary STLs of the validation parts from their OpenSCAD sources, with the
# examples' exporter (canonical triangle order, checked by check_stl.py).
# Usage: bench/validation/export.sh [name.scad ...]   (default: every *.scad here)
here="$(cd "$(dirname "$0")" && pwd)"
EXPORT_DIR="$here" exec "$here/../../examples/models/export.sh" "$@"
