#!/usr/bin/env bash
# The GPU check in one command, for a machine with an NVIDIA GPU and the
# CUDA toolkit (a few minutes): builds the CUDA back end, runs the gpu tests
# (the shared host-device functions on the device; the SRD device step
# against the CPU systems after 1 and 100 steps, per-cell momentum, energy
# at eps = 1, cooling statistics) and the SRD GPU benchmark at 1e6, 1e7 and
# 1e8 particles, then prints a short summary. Where no device is usable the
# tests say so and skip, and the benchmark is not run.
#   bench/gpu_check.sh [build-directory] [particle counts ...]
set -uo pipefail
cd "$(dirname "$0")/.."
build="${1:-build-cuda}"
shift || true
export PATH="$PATH:/usr/local/cuda/bin"
command -v nvcc > /dev/null || { echo "nvcc not found: install the CUDA toolkit" >&2; exit 1; }
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DGRANFLOW_CUDA=ON -DGRANFLOW_TESTS=OFF \
  -DGRANFLOW_BENCH=OFF > "$build.configure.log" || { cat "$build.configure.log"; exit 1; }
cmake --build "$build" --target granflow_cuda_probe granflow_gpu_test granflow_srd_gpu_bench || exit 1
"$build/cuda/granflow_cuda_probe"
"$build/cuda/granflow_gpu_test" 2>&1 | tee "$build.gpu_test.log"
tests=${PIPESTATUS[0]}
bench=skipped
if grep -q "SKIPPED" "$build.gpu_test.log"; then
  echo "no usable device: the benchmark is not run"
else
  "$build/cuda/granflow_srd_gpu_bench" "$@" | tee "$build.gpu_bench.log"
  bench=$([[ ${PIPESTATUS[0]} -eq 0 ]] && echo ran || echo failed)
fi
echo
count() { grep -oE "^\[  $1 *\] [0-9]+ tests?" "$build.gpu_test.log" | grep -oE '[0-9]+' | head -1; }
echo "summary: gpu tests passed $(count PASSED || echo 0), failed $(count FAILED || echo 0)," \
  "skipped $(count SKIPPED || echo 0); benchmark $bench"
[[ -f "$build.gpu_bench.log" && $bench == ran ]] && grep -E '^ +[0-9.e+]+ +[0-9]+ ' "$build.gpu_bench.log"
exit "$tests"
