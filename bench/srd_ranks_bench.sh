#!/usr/bin/env bash
# Weak scaling of one SRD fluid over MPI ranks on one machine: gsrd_cooling
# with 10^6 particles per rank (50 x 50 x 40 cells per rank, n0 = 10), one
# thread per rank, on 1 rank (the plain step) and on 2 ranks (the slab
# step), the two taking turns in every round (this machine's speed drifts).
# The time of a step is the step systems' total in /profile, so set-up and
# the few outputs are left out. Prints each round, the medians, the
# efficiency t(1 rank) / t(2 ranks), and each rank's parts of the 2-rank step.
#
#   bench/srd_ranks_bench.sh [GRANFLOW] [ROUNDS] [STEPS]
#   (default: build/granflow, 5 rounds, 200 steps; a -DGRANFLOW_MPI=ON build)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
granflow=${1:-$root/build/granflow}
rounds=${2:-5}
steps=${3:-200}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
common=(--set run.steps="$steps" --set output.points_per_decade=1 -q --threads 1)

step_seconds() {  # step_seconds FILE: mean seconds per step of the step systems
  /usr/bin/python3 - "$1" "$steps" <<'PY'
import sys, h5py
f = h5py.File(sys.argv[1], "r")
names = [n.decode() if isinstance(n, bytes) else n for n in f["profile/system"][()]]
total = f["profile/total_seconds"][()]
step = ("srd_streaming", "srd_grid_shift", "srd_cell_binning", "srd_cell_reduction", "srd_rotation", "srd_domain_step")
print(sum(t for n, t in zip(names, total) if n in step) / int(sys.argv[2]))
PY
}

one=() two=()
for round in $(seq 1 "$rounds"); do
  "$granflow" run "$root/scenarios/gsrd_cooling.toml" "${common[@]}" --set 'system.cells=[50,50,40]' -o "$scratch/one.h5"
  mpirun -np 2 --oversubscribe --bind-to none "$granflow" run "$root/scenarios/gsrd_cooling.toml" "${common[@]}" \
    --set 'system.cells=[50,50,80]' -o "$scratch/two.h5"
  one+=("$(step_seconds "$scratch/one.h5")")
  two+=("$(step_seconds "$scratch/two.h5")")
  echo "round $round: 1 rank ${one[-1]} s/step, 2 ranks ${two[-1]} s/step"
done
/usr/bin/python3 - "${one[*]}" "${two[*]}" "$scratch/two.h5" "$steps" <<'PY'
import sys, statistics, h5py
one = [float(x) for x in sys.argv[1].split()]
two = [float(x) for x in sys.argv[2].split()]
ratios = [a / b for a, b in zip(one, two)]
print(f"median 1 rank {statistics.median(one) * 1e3:.1f} ms/step, 2 ranks {statistics.median(two) * 1e3:.1f} ms/step")
print(f"weak-scaling efficiency: median of the rounds' ratios {statistics.median(ratios):.3f} "
      f"(range {min(ratios):.3f}-{max(ratios):.3f})")
f = h5py.File(sys.argv[3], "r")
names = [n.decode() if isinstance(n, bytes) else n for n in f["profile/system"][()]]
rows = dict(zip(names, f["profile/total_seconds"][()]))
parts = [n.split(".")[-1] for n in names if n.startswith("srd_domain_step.rank0.")]
print("parts of the 2-rank step, ms/step:", " ".join(f"{'rank ' + str(r):>8}" for r in range(2)))
for part in parts:
    print(f"  {part:<16}", " ".join(f"{rows[f'srd_domain_step.rank{r}.{part}'] / int(sys.argv[4]) * 1e3:8.2f}" for r in range(2)))
PY
