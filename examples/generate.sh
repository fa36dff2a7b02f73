#!/usr/bin/env bash
# Generates supports for every example (in its designed pose: --orient keep) into
# examples/generated/<name>/: the parametric SCAD (with its template library and the placed model it
# imports), the report, and pictures (model grey, supports orange). Needs a build (scripts/build.sh)
# and, for the pictures, Debian's openscad and xvfb (scripts/install-deps.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
cli=build/generator/clever-support
[ -x "$cli" ] || scripts/build.sh >/dev/null
for stl in examples/models/*.stl; do
  name=$(basename "${stl%.stl}")
  out=examples/generated/$name
  tmp=$(mktemp -d)
  "$cli" "$stl" --orient keep --no-timings --preview -q --out "$tmp"
  mkdir -p "$out"
  cp "$tmp/$name.scad" "$tmp/clever_support.scad" "$tmp/$name.model.stl" "$tmp/$name.report.json" "$out/"
  cp "$tmp/$name-front.png" "$out/$name.png"
  rm -rf "$tmp"
  echo "$out"
done
