#!/usr/bin/env bash
# Weak scaling of one soft-sphere system over MPI ranks on one machine: the
# vibrated bed (LAMMPS's shaken-bed workload, frictionless) with 10^5
# spheres per rank, one thread per rank: 10^5 spheres in a 72 x 72 x 80 box
# on 1 rank (the plain chain), 2 x 10^5 in a 72 x 72 x 160 box on 2 ranks
# (the slab step: each rank's slab is the one-rank bed's shape), and, as the
# machine's own limit, two one-rank runs at once (two processes sharing the
# memory bus and caches, with nothing to exchange). The three take turns in
# every round (this machine's speed drifts). The time of a step is the step
# systems' total in /profile, so set-up and outputs are left out. Prints each
# round, the medians, the efficiencies t(1) / t(2 ranks) and
# t(1, beside another) / t(2 ranks), and each rank's parts of the 2-rank step.
#
#   bench/dem_ranks_bench.sh [GRANFLOW] [ROUNDS] [T_STOP]
#   (default: build/granflow, 5 rounds, t = 1, about 925 steps; a
#   -DGRANFLOW_MPI=ON build)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
granflow=${1:-$root/build/granflow}
rounds=${2:-5}
t_stop=${3:-1}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
bed="$root/scenarios/vibrated_bed.toml"
common=(--set run.t_stop="$t_stop" -q --threads 1)
one_rank=(--set 'system.box=[72,72,80]' --set 'bed.fill=[0,71,0,71,0.6,20.5]' --set system.count=100000)
two_ranks=(--set 'system.box=[72,72,160]' --set 'bed.fill=[0,71,0,71,0.6,40.5]' --set system.count=200000)
step_names=(dem_kick_drift dem_neighbour_list dem_contact_forces dem_kick dem_energy_account dem_domain_step)
step_seconds() { /usr/bin/python3 "$root/bench/ranks_profile.py" step "$1" "${step_names[@]}"; }

one=() two=() beside=()
for round in $(seq 1 "$rounds"); do
  "$granflow" run "$bed" "${common[@]}" "${one_rank[@]}" -o "$scratch/one.h5"
  mpirun -np 2 --oversubscribe --bind-to none "$granflow" run "$bed" "${common[@]}" "${two_ranks[@]}" -o "$scratch/two.h5"
  "$granflow" run "$bed" "${common[@]}" "${one_rank[@]}" -o "$scratch/beside_a.h5" &
  "$granflow" run "$bed" "${common[@]}" "${one_rank[@]}" -o "$scratch/beside_b.h5"
  wait
  one+=("$(step_seconds "$scratch/one.h5")")
  two+=("$(step_seconds "$scratch/two.h5")")
  beside+=("$(step_seconds "$scratch/beside_a.h5")")
  echo "round $round: 1 rank ${one[-1]} s/step, 2 ranks ${two[-1]} s/step, 1 rank beside another ${beside[-1]} s/step"
done
profile="$root/bench/ranks_profile.py"
/usr/bin/python3 "$profile" compare "1 rank" "${one[*]}" "2 ranks" "${two[*]}" "weak-scaling efficiency"
/usr/bin/python3 "$profile" compare "1 rank beside another" "${beside[*]}" "2 ranks" "${two[*]}" \
  "efficiency against a one-rank run beside another"
/usr/bin/python3 "$profile" parts "$scratch/two.h5" dem_domain_step
