#!/usr/bin/env bash
# Builds the configuration and sweep-file fuzz target with clang (libFuzzer,
# ASan, UBSan) and runs it for SECONDS (default 60) from a seed corpus of the
# scenario and sweep files and a few lists; exits non-zero on any finding.
#   tests/fuzz/run_config_fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds="${1:-60}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
clang++ -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined -I. \
  engine/core/config.cpp engine/app/sweep_file.cpp tests/fuzz/config_fuzz.cpp $(pkg-config --cflags --libs tomlplusplus fmt) -o "$work/config_fuzz"
mkdir -p "$work/corpus"
cp scenarios/*.toml "$work/corpus/"
printf 'system.cells=[46, 46, 46]\n[[walls]]\naxis = "x"\nposition = 0.5\n' > "$work/corpus/lists.toml"
printf 'walls=[{axis = "z"}]\n' > "$work/corpus/set.toml"
printf 'scenario_file = "h.toml"\nrepeats = 2\nsummary = ["t"]\n[set]\n"system.count" = 20\n[grid]\nsystem.radius = [0.1, 0.2]\n[zip]\nsystem.boundary = ["periodic", "reflecting"]\n[[points]]\nwalls = [{axis = "x"}]\n' > "$work/corpus/sweep_grid.toml"
# Any bytes: the loader refuses non-ASCII outside strings before toml++ sees
# it (toml++ 3.3 has undefined behaviour on some non-ASCII bare keys).
"$work/config_fuzz" "$work/corpus" -max_total_time="$seconds" -max_len=4096 -print_final_stats=1 \
  -artifact_prefix="$work/" 2>&1 | tail -15
