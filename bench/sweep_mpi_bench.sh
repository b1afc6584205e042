#!/usr/bin/env bash
# Efficiency of `granflow sweep` over MPI ranks on one machine: the same
# sweep as one local worker, two local workers, two ranks of one worker and
# one rank of two workers, each into a fresh directory, the four taking
# turns in every round (this machine's speed drifts, so they are interleaved
# rather than run in blocks). Prints every wall time, the medians and each
# one's speed-up over one local worker.
#
#   bench/sweep_mpi_bench.sh [GRANFLOW] [SWEEP.toml] [ROUNDS]
#   (default: build/granflow, scenarios/crater_mass_sweep.toml, 3 rounds;
#    a build with -DGRANFLOW_MPI=ON and mpirun on the PATH)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
granflow=${1:-$root/build/granflow}
sweep=${2:-$root/scenarios/crater_mass_sweep.toml}
rounds=${3:-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

names=("local -j 1" "local -j 2" "mpirun -np 2, -j 1" "mpirun -np 1, -j 2")
run() {  # run INDEX DIR
  case $1 in
    0) "$granflow" sweep "$sweep" -j 1 -o "$2" -q ;;
    1) "$granflow" sweep "$sweep" -j 2 -o "$2" -q ;;
    2) mpirun -np 2 --oversubscribe "$granflow" sweep "$sweep" -j 1 -o "$2" -q ;;
    3) mpirun -np 1 --bind-to none "$granflow" sweep "$sweep" -j 2 -o "$2" -q ;;
  esac
}
declare -a times=("" "" "" "")
for ((round = 1; round <= rounds; ++round)); do
  line="round $round:"
  for ((k = 0; k < 4; ++k)); do
    c=$(((k + round - 1) % 4))  # each configuration takes each place in turn
    rm -rf "$scratch/out"
    start=$(date +%s.%N)
    run "$c" "$scratch/out" > /dev/null
    end=$(date +%s.%N)
    seconds=$(awk -v a="$start" -v b="$end" 'BEGIN {print b - a}')
    times[$c]="${times[$c]} $seconds"
    line="$line  ${names[$c]} $(printf '%.2f' "$seconds") s;"
  done
  echo "$line"
done
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{v[NR]=$1} END {print (NR%2 ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2)}'; }
base=$(echo "${times[0]}" | median)
for ((c = 0; c < 4; ++c)); do
  m=$(echo "${times[$c]}" | median)
  cores=$((c > 0 ? 2 : 1))
  awk -v name="${names[$c]}" -v m="$m" -v base="$base" -v cores="$cores" \
    'BEGIN {printf "%-20s median %6.2f s  speed-up %.2f  per core %.2f\n", name, m, base / m, base / m / cores}'
done
