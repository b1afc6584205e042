#!/usr/bin/env bash
# The installed CMake package works for a separate project: install granflow
# into a fresh prefix, configure and build docs/examples/sonine against it
# with find_package(granflow), run it and check its H5MD output.
set -eu
build="$1"
source="$2"
cxx_flags="${3:-}"
linker_flags="${4:-}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
generator=()
command -v ninja > /dev/null && generator=(-G Ninja)
cmake -S "$source/docs/examples/sonine" -B "$work/example" "${generator[@]}" \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_CXX_FLAGS="$cxx_flags" -DCMAKE_EXE_LINKER_FLAGS="$linker_flags" \
  > "$work/configure.log"
cmake --build "$work/example" > "$work/build.log"
cd "$work"
"$work/example/sonine_cooling" run "$source/docs/examples/sonine/sonine.toml" --set collision.restitution=0.8 \
  --set run.t_stop=20 -q | tee "$work/run.log"
grep -q '^xi = 0.8: a2 = ' "$work/run.log"
"$work/prefix/bin/granflow" info "$work/sonine.h5md" | tee "$work/info.log" | grep -q '/observables/sonine_a2/value'
grep -q '/observables/kinetic_energy/value' "$work/info.log"
grep -q '/profile/system' "$work/info.log"
# The user's program has the built-in scenarios too, and their keys.
"$work/example/sonine_cooling" list | grep -q '^  haff_cooling'
"$work/example/sonine_cooling" keys sonine_cooling | grep -q '^collision.restitution'
# Bad input in the user's program is reported as granflow reports it.
status=0
"$work/example/sonine_cooling" run "$source/docs/examples/sonine/sonine.toml" --set collision.restitution=2 \
  2> "$work/err.log" || status=$?
[[ $status -eq 2 ]] && grep -q "'collision.restitution' = 2 is out of range" "$work/err.log"
echo "package test passed"
