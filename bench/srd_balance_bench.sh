#!/usr/bin/env bash
# What load balance gains for one SRD fluid over 2 MPI ranks whose density
# falls off along the slab axis: gsrd_cooling from a stored state of 2·10^6
# particles (50 x 50 x 80 cells, n0 = 10, elastic, kT = 1) with
# z -> L (z / L)^2, so that the lower half holds 71 % of them (the busiest
# slab 1.41 times the mean). One
# thread per rank; the slabs fixed (balance.every_steps = 0) and rebalanced
# every 10 steps take turns in every round (this machine's speed drifts).
# Prints each round's time per step (the step systems' total in /profile),
# the medians and their ratio.
#
#   bench/srd_balance_bench.sh [GRANFLOW] [ROUNDS] [STEPS]
#   (default: build/granflow, 5 rounds, 200 steps; a -DGRANFLOW_MPI=ON build)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
granflow=${1:-$root/build/granflow}
rounds=${2:-5}
steps=${3:-200}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cooling="$root/scenarios/gsrd_cooling.toml"
"$granflow" run "$cooling" --set 'system.cells=[50,50,80]' --set run.steps=1 --set output.positions=final -q \
  -o "$scratch/even.h5"
# kT = 1 (a stored state's velocities replace srd.temperature): the
# profile then spreads by a few cells in the run, not across the box.
/usr/bin/python3 "$root/tools/denser_at_one_end.py" "$scratch/even.h5" "$scratch/lumpy.h5" --temperature 1
common=(--set 'system.cells=[50,50,80]' --set initial.from="$scratch/lumpy.h5" --set srd.restitution=1
        --set run.steps="$steps" --set output.points_per_decade=1 -q --threads 1)
step_seconds() { /usr/bin/python3 "$root/bench/ranks_profile.py" step "$1" srd_domain_step; }
fixed=() balanced=()
for round in $(seq 1 "$rounds"); do
  mpirun -np 2 --oversubscribe --bind-to none "$granflow" run "$cooling" "${common[@]}" --set balance.every_steps=0 \
    -o "$scratch/fixed.h5"
  mpirun -np 2 --oversubscribe --bind-to none "$granflow" run "$cooling" "${common[@]}" --set balance.every_steps=10 \
    -o "$scratch/balanced.h5"
  fixed+=("$(step_seconds "$scratch/fixed.h5")")
  balanced+=("$(step_seconds "$scratch/balanced.h5")")
  echo "round $round: fixed slabs ${fixed[-1]} s/step, rebalanced ${balanced[-1]} s/step"
done
/usr/bin/python3 "$root/bench/ranks_profile.py" compare "fixed" "${fixed[*]}" "rebalanced" "${balanced[*]}" "speed-up"
