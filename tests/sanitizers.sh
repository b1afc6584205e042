#!/usr/bin/env bash
# The sanitizer stage of CI: builds everything with AddressSanitizer and
# UndefinedBehaviorSanitizer and runs the whole test set except the `long`
# physics checks on it (any report fails); the package test builds its
# consumer with the same flags.
#   tests/sanitizers.sh [build-directory]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build-sanitize}"
# UBSan checks stay recoverable so that the suppression file can apply;
# halt_on_error below makes every unsuppressed report fatal. -g1 keeps line
# numbers in reports while the link stays small; -O1 (assertions on) builds in
# a third of the time of -O3 on 2 cores.
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -g1"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-O1 -DCMAKE_C_FLAGS_RELEASE=-O1 -DGRANFLOW_BENCH=OFF -DGRANFLOW_NATIVE=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" \
  -DCMAKE_SHARED_LINKER_FLAGS="$flags" > "$build.configure.log"
cmake --build "$build"
# oneTBB's flow graph casts its tasks in a way UBSan's vptr check reports (its code, not granflow's).
export UBSAN_OPTIONS="suppressions=$PWD/tests/ubsan.supp:print_stacktrace=1:halt_on_error=1"
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
# The interrupt test's delays are scaled for the instrumented program's speed.
export GRANFLOW_SLOWDOWN=4
ctest --test-dir "$build" --output-on-failure -LE long -j2
echo "sanitizer stage passed"
