#!/usr/bin/env bash
# The sanitizer stage: builds with AddressSanitizer and UndefinedBehaviorSanitizer
# and runs tests on the instrumented build (any report fails).
#   tests/sanitizers.sh [build-directory]        every test but the `long` ones
#                                                (about 25 minutes on 2 cores);
#                                                the package test builds its
#                                                consumer with the same flags
#   tests/sanitizers.sh --ci [build-directory]   CI's share: the unit tests and
#                                                the damaged-file tests
#                                                (checkpoint corruption, full
#                                                disk, export), about 6 minutes
set -euo pipefail
cd "$(dirname "$0")/.."
ci=false
if [[ "${1:-}" == "--ci" ]]; then ci=true; shift; fi
build="${1:-build-sanitize}"
# UBSan checks stay recoverable so that the suppression file can apply;
# halt_on_error below makes every unsuppressed report fatal. -g1 keeps line
# numbers in reports while the link stays small; -O0 (assertions on) builds in
# 0.6 of the time of -O1 (a scenario file: 34 s against 58 s), and the tests
# run here are short. At -O0 most of a file's time goes to generating the
# templates it instantiates, so the libraries are built as unity sources
# (several files to one, each template generated once): 300 s of compiling
# the layers below the scenarios instead of 460.
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -g1"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-O0 -DCMAKE_C_FLAGS_RELEASE=-O0 \
  -DGRANFLOW_BENCH=OFF -DGRANFLOW_NATIVE=OFF -DCMAKE_UNITY_BUILD=ON \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" \
  -DCMAKE_SHARED_LINKER_FLAGS="$flags" > "$build.configure.log"
# oneTBB's flow graph casts its tasks in a way UBSan's vptr check reports (its code, not granflow's).
export UBSAN_OPTIONS="suppressions=$PWD/tests/ubsan.supp:print_stacktrace=1:halt_on_error=1"
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
# The interrupt test's delays are scaled for the instrumented (-O0) program's speed.
export GRANFLOW_SLOWDOWN=8
if $ci; then
  unit_tests=(appendix_b_test inelastic_collapse_test event_calendar_test config_test schedule_test rng_test
              random_placement_test multiple_tau_msd_test sweep_plan_test sde_kernel_test srd_step_test key_units_test
              pair_kernel_test thread_domains_test contact_search_test occupied_cells_test dem_watchdog_test
              dem_walls_test trigger_test)
  cmake --build "$build" --target granflow_cli "${unit_tests[@]}"
  # Not the two million-collision energy checks (AppendixB3): over three
  # minutes here for what the other EDMD unit tests cover; the
  # uninstrumented build runs them.
  ctest --test-dir "$build" --output-on-failure -j2 -L unit -E '^AppendixB3[.]'
  ctest --test-dir "$build" --output-on-failure -j2 -R '^(checkpoint_corruption_test|full_disk_test|export_test)$'
else
  cmake --build "$build"
  ctest --test-dir "$build" --output-on-failure -LE long -j2
fi
echo "sanitizer stage passed"
