#!/usr/bin/env bash
# The GPU check in one command, for a machine with an NVIDIA GPU and the
# CUDA toolkit (a few minutes): builds the CUDA back end and runs the
# host-device agreement test (Philox words, one SDE step, one pair collision
# on the device against the host). Where no device is usable the test says
# so and skips.
#   bench/gpu_check.sh [build-directory]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build-cuda}"
export PATH="$PATH:/usr/local/cuda/bin"
command -v nvcc > /dev/null || { echo "nvcc not found: install the CUDA toolkit" >&2; exit 1; }
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DGRANFLOW_CUDA=ON -DGRANFLOW_TESTS=OFF \
  -DGRANFLOW_BENCH=OFF > "$build.configure.log"
cmake --build "$build" --target granflow_cuda_probe granflow_gpu_test
"$build/cuda/granflow_cuda_probe"
"$build/cuda/granflow_gpu_test"
