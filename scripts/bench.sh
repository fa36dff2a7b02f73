#!/usr/bin/env bash
# Benchmark suite (bench/README.md): builds the generator and the microbenchmarks into build-bench/
# (Release, -DCS_BENCH=ON), runs the microbenchmarks, then bench/run_bench.py.
#
#   scripts/bench.sh --quick                 # bridge, u_overhang, extruder_idler, arches (a few minutes)
#   scripts/bench.sh                         # full: all shared benchmark models + examples, scaling, orientation
#   scripts/bench.sh --models armadillo,spot --out /tmp/res
#   scripts/bench.sh --validation            # only the validation parts (bench/validation), per model
#   scripts/bench.sh --no-micro ...          # skip the Google Benchmark run
#   scripts/bench.sh --no-build ...          # use build-bench/ as it is
# Every other argument goes to bench/run_bench.py (see its --help: --scaling, --orient, --no-main,
# --repeats, --jobs, --report-only, ...). Results: bench/results/ (quick: bench/results/quick/).
set -euo pipefail
cd "$(dirname "$0")/.."

micro=1 build=1 quick=0 validation=0 out=""
pass=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --no-micro) micro=0 ;;
    --no-build) build=0 ;;
    --quick) quick=1; pass+=("$1") ;;
    --validation) validation=1; micro=0; pass+=("$1") ;;  # per model only, reported apart (bench/validation)
    --out) out="$2"; pass+=("$1" "$2"); shift ;;
    --out=*) out="${1#--out=}"; pass+=("$1") ;;
    *) pass+=("$1") ;;
  esac
  shift
done
if [[ -z "$out" ]]; then
  if [[ $quick == 1 ]]; then out=bench/results/quick
  elif [[ $validation == 1 ]]; then out=bench/results/validation
  else out=bench/results; fi
fi
mkdir -p "$out"

if [[ $build == 1 ]]; then
  # Tests are off here so the benchmark does not depend on the test tree configuring.
  cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DCS_BENCH=ON -DCS_TESTS=OFF >/dev/null
  cmake --build build-bench -j"$(nproc 2>/dev/null || echo 2)" >/dev/null
fi
bin=build-bench/generator/clever-support
[[ -x $bin ]] || { echo "bench.sh: $bin missing (build failed?)" >&2; exit 2; }

# Cura machine definitions: the one thing cached across runs.
bench/slicers/fetch_cura_defs.sh >/dev/null

if [[ $micro == 1 && -x build-bench/bench/bench_kernels ]]; then
  echo "== microbenchmarks -> $out/micro.json"
  if [[ $quick == 1 ]]; then mt=0.05; else mt=0.5; fi
  build-bench/bench/bench_kernels --benchmark_min_time=$mt --benchmark_out="$out/micro.json" \
    --benchmark_out_format=json --benchmark_format=console
fi

echo "== run_bench.py"
exec /usr/bin/python3 bench/run_bench.py --bin "$bin" "${pass[@]}"
