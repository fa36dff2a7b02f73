#!/usr/bin/env bash
# Fingerprints every output file of the generator on the examples (both poses) and the shared
# benchmark models (benchmark.json scale: kept pose, --buildplate-only, and the pose the orientation
# search picks, as a user runs it), for checking that a restructuring changes
# nothing: run it before and after, then diff the two lists.
#   bench/same_outputs.sh [cli] > before.txt ; ...change... ; bench/same_outputs.sh > after.txt
#   diff before.txt after.txt
# Reports are written with --no-timings, so equal inputs give byte-identical files.
# Set SAME_OUTPUTS_QUICK=1 to leave out the slow Menger sponge and nefertiti.
set -euo pipefail
cd "$(dirname "$0")/.."
cli=${1:-build/generator/clever-support}
shared=${SHARED:-../shared/models}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() {  # name, then arguments for the generator
  local name=$1; shift
  if "$cli" "$@" --no-timings -q --out "$tmp/$name" >"$tmp/log" 2>&1; then
    # A .scad records the absolute input path: the checkout is written as <checkout>, so checkouts compare.
    find "$tmp/$name" -name '*.scad' -exec sed -i "s|$PWD/|<checkout>/|g" {} +
    (cd "$tmp/$name" && find . -type f | LC_ALL=C sort | xargs sha256sum | sed "s|  \./|  $name/|")
  else
    echo "FAILED $name: $(head -c 300 "$tmp/log")"
  fi
  rm -rf "${tmp:?}/$name"
}
for stl in examples/models/*.stl; do
  n=$(basename "${stl%.stl}")
  run "example-$n-keep" "$stl" --orient keep
  run "example-$n-auto" "$stl"
done
for stl in tests/data/cad/*.stl; do
  [ -f "$stl" ] && run "cad-$(basename "${stl%.stl}")" "$stl" --orient keep
done
if [ -f "$shared/benchmark.json" ]; then
  python3 - "$shared" <<'PY' >"$tmp/models"
import json, sys
d = sys.argv[1]
for m in json.load(open(d + "/benchmark.json"))["models"]:
    print(m["file"], m["scale"])
PY
  while read -r file scale; do
    n=${file%.*}
    if [ -n "${SAME_OUTPUTS_QUICK:-}" ] && [[ $n == menger* || $n == nefertiti* ]]; then continue; fi
    run "$n" "$shared/$file" --orient keep --scale "$scale"
    run "$n-bp" "$shared/$file" --orient keep --scale "$scale" --buildplate-only
    run "$n-auto" "$shared/$file" --scale "$scale"
  done <"$tmp/models"
fi
