#!/usr/bin/env bash
# Weak scaling of one SRD fluid over MPI ranks on one machine: gsrd_cooling
# with 10^6 particles per rank (50 x 50 x 40 cells per rank, n0 = 10), one
# thread per rank, on 1 rank (the plain step), on 2 ranks (the slab step)
# and, as the machine's own limit, two one-rank runs at once (two processes
# sharing the memory bus and caches, with nothing to exchange), the three
# taking turns in every round (this machine's speed drifts). The time of a
# step is the step systems' total in /profile, so set-up and the few outputs
# are left out. Prints each round, the medians, the efficiencies
# t(1 rank) / t(2 ranks), t(1 rank) / t(1 rank beside another) (what the
# machine allows) and t(1 rank beside another) / t(2 ranks) (what the
# decomposition costs), and each rank's parts of the 2-rank step.
#
#   bench/srd_ranks_bench.sh [GRANFLOW] [ROUNDS] [STEPS] [BASELINE]
#   (default: build/granflow, 5 rounds, 200 steps; a -DGRANFLOW_MPI=ON build)
# With BASELINE (another build's granflow), every round also runs its
# 2-rank step, and the two builds' 2-rank steps are compared round by round.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
granflow=${1:-$root/build/granflow}
rounds=${2:-5}
steps=${3:-200}
baseline=${4:-}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
common=(--set run.steps="$steps" --set output.points_per_decade=1 -q --threads 1)

step_names=(srd_streaming srd_grid_shift srd_cell_binning srd_cell_reduction srd_rotation srd_domain_step)
step_seconds() { /usr/bin/python3 "$root/bench/ranks_profile.py" step "$1" "${step_names[@]}"; }

on_two_ranks() {  # on_two_ranks GRANFLOW OUT
  mpirun -np 2 --oversubscribe --bind-to none "$1" run "$root/scenarios/gsrd_cooling.toml" "${common[@]}" \
    --set 'system.cells=[50,50,80]' -o "$2"
}
on_one_rank() {  # on_one_rank OUT
  "$granflow" run "$root/scenarios/gsrd_cooling.toml" "${common[@]}" --set 'system.cells=[50,50,40]' -o "$1"
}
one=() two=() beside=() base=()
for round in $(seq 1 "$rounds"); do
  on_one_rank "$scratch/one.h5"
  on_two_ranks "$granflow" "$scratch/two.h5"
  on_one_rank "$scratch/beside_a.h5" &
  on_one_rank "$scratch/beside_b.h5"
  wait
  one+=("$(step_seconds "$scratch/one.h5")")
  two+=("$(step_seconds "$scratch/two.h5")")
  beside+=("$(step_seconds "$scratch/beside_a.h5")")
  echo "round $round: 1 rank ${one[-1]} s/step, 2 ranks ${two[-1]} s/step, 1 rank beside another ${beside[-1]} s/step"
  if [[ -n "$baseline" ]]; then
    on_two_ranks "$baseline" "$scratch/base.h5"
    base+=("$(step_seconds "$scratch/base.h5")")
    echo "round $round: baseline on 2 ranks ${base[-1]} s/step"
  fi
done
/usr/bin/python3 "$root/bench/ranks_profile.py" compare "1 rank" "${one[*]}" "2 ranks" "${two[*]}" "weak-scaling efficiency"
/usr/bin/python3 "$root/bench/ranks_profile.py" compare "1 rank" "${one[*]}" "1 rank beside another" "${beside[*]}" \
  "the machine's limit (two runs at once, nothing exchanged)"
/usr/bin/python3 "$root/bench/ranks_profile.py" compare "1 rank beside another" "${beside[*]}" "2 ranks" "${two[*]}" \
  "efficiency against a one-rank run beside another"
if [[ -n "$baseline" ]]; then
  /usr/bin/python3 "$root/bench/ranks_profile.py" compare "2 ranks" "${two[*]}" "baseline on 2 ranks" "${base[*]}" \
    "2-rank step time against the baseline's"
fi
/usr/bin/python3 "$root/bench/ranks_profile.py" parts "$scratch/two.h5" srd_domain_step
