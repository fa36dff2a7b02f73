#!/usr/bin/env bash
# Installs what is missing, builds, generates tree supports for a bundled example, renders the
# generated OpenSCAD into one printable solid, and prints where everything is.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh >/dev/null
model=${1:-examples/models/molecule.stl}
name=$(basename "${model%.*}")
out=out/$name
echo
echo "== clever-support $model"
build/generator/clever-support --out "$out" "$model"
echo
echo "== check (coverage, penetration, grounding, closed solids, angles)"
build/generator/clever-support check --model "$out/$name.model.stl" --supports "$out/$name.supports.stl"
echo
echo "== render $out/$name.scad with OpenSCAD"
build/generator/clever-support render "$out/$name.scad"
echo
echo "Outputs in $out/:"
ls -1 "$out" | sed 's/^/  /'
echo "Print: open $out/$name.3mf in Cura (import $out/clever_support.curaprofile once, on a Creality printer"
echo "clever_support_creality.curaprofile) or"
echo "$out/$name.prusa.3mf in PrusaSlicer, so the struts print as supports (README 'Printing in Cura');"
echo "or open $out/$name.scad in OpenSCAD to tweak k, d_min, tips, feet."
