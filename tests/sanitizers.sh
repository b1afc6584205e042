#!/usr/bin/env bash
# The sanitizer stage of CI: builds the program and the fast test programs
# with AddressSanitizer and UndefinedBehaviorSanitizer (any report fails),
# runs them, and runs the command-line tests on the instrumented program,
# checkpoint corruption included.
#   tests/sanitizers.sh [build-directory]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build-sanitize}"
# UBSan checks stay recoverable so that the suppression file can apply;
# halt_on_error below makes every unsuppressed report fatal.
flags="-fsanitize=address,undefined -fno-omit-frame-pointer"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGRANFLOW_BENCH=OFF -DGRANFLOW_NATIVE=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" > "$build.configure.log"
tests=(config_test schedule_test rng_test event_calendar_test reference_comparison_test sde_kernel_test
       multiple_tau_msd_test inelastic_collapse_test)
cmake --build "$build" --target granflow_cli "${tests[@]}"
# oneTBB's flow graph casts its tasks in a way UBSan's vptr check reports (its code, not granflow's).
export UBSAN_OPTIONS="suppressions=$PWD/tests/ubsan.supp:print_stacktrace=1:halt_on_error=1"
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
for t in "${tests[@]}"; do "$build/tests/$t" --gtest_brief=1; done
tests/cli/checkpoint_corruption_test.sh "$build/granflow" scenarios/haff_cooling.toml > "$build.corruption.log" || {
  cat "$build.corruption.log"; exit 1; }
GRANFLOW_SLOWDOWN=4 tests/cli/interrupt_test.sh "$build/granflow" scenarios
echo "sanitizer stage passed"
