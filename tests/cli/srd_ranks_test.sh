#!/usr/bin/env bash
# One SRD system over MPI ranks (`mpirun -np K granflow run`, a
# -DGRANFLOW_MPI=ON build; systems/srd/srd_domain_step.hpp):
#  - gsrd_cooling in 3D and 2D on 2 and 3 ranks gives the one-rank result,
#    with particle frames and fields: the same cells, particles and random
#    numbers, the straddling cells' sums in another order, so every dataset
#    agrees to round-off (measured 1e-12 of its largest value; checked at
#    1e-9), and integer ones exactly;
#  - on a given number of ranks the result does not depend on the threads;
#  - no rank holds the whole system: each one's memory grows with the
#    system well below one process's (the observers run on every rank,
#    checkpoints are written by rank and read back by slab);
#  - a finished 2-rank run extended with --resume on 2 ranks equals one
#    2-rank run bit for bit, and extended on 3 ranks equals a 3-rank run to
#    round-off; /provenance records the ranks of each segment;
#  - SIGINT to mpirun (which sends the ranks SIGTERM) stops every rank at
#    one step with a checkpoint and no result file, and --resume on 3 ranks
#    finishes it; SIGTERM to one rank alone stops them all alike, and the
#    run resumes bit for bit; a rank killed with
#    SIGKILL ends the job, and --resume from the last periodic checkpoint
#    gives the uninterrupted result bit for bit;
#  - between walls (the slabs then lie along a periodic axis): Poiseuille
#    flow (no-slip walls with ghost particles, body force, global
#    thermostat) and the shaken bed (a moving floor, gravity, the energy
#    ledger), and Lees-Edwards shear (srd_viscosity with its thermostat and
#    stress sampler; the granular shear band with particle frames; in 2D the
#    planes lie at the slabs' periodic edge, in 3D inside every slab), 2D
#    and 3D, on 2 and 3 ranks, give the one-rank result to round-off, and the
#    ledger balances on ranks as on one;
#  - load balance: the slabs' bounds move to even out the particles of a
#    fluid denser at one end, with the one-rank result to round-off and a
#    resume bit for bit across a rebalance;
#  - failed physics (a particle stranded on a wall; a velocity that blows
#    the temperature up) ends every rank with exit 3 and one diagnosis; the
#    warning of cells clamped at eps_eff = 0 is one rank's, said once;
#  - a damaged checkpoint is refused once, before any rank reads its slab;
#  - what is not distributed is refused once, on rank 0, with exit status 2.
set -u
source "$(dirname "$0")/ranks_common.sh"  # GRANFLOW MPIEXEC SCENARIOS

cooling="$scenarios/gsrd_cooling.toml"
common=(--set srd.restitution=0.98 --set srd.rotation_angle=10 --set output.positions=all
        --set fields.every_steps=100 --set fields.window=10 -q)
three_d=(--set 'system.cells=[8,8,9]' --set run.steps=400 "${common[@]}")
two_d=(--set system.dimension=2 --set 'system.cells=[24,24]' --set run.steps=400 "${common[@]}")
"$granflow" run "$cooling" "${three_d[@]}" -o "$work/one_3d.h5" || fail "one rank (3D) exited with $?"
"$granflow" run "$cooling" "${two_d[@]}" -o "$work/one_2d.h5" || fail "one rank (2D) exited with $?"
for k in 2 3; do
  ranks "$k" run "$cooling" "${three_d[@]}" -o "$work/ranks${k}_3d.h5" || fail "$k ranks (3D) exited with $?"
  agree "$work/one_3d.h5" "$work/ranks${k}_3d.h5" 1e-9
  ranks "$k" run "$cooling" "${two_d[@]}" -o "$work/ranks${k}_2d.h5" || fail "$k ranks (2D) exited with $?"
  agree "$work/one_2d.h5" "$work/ranks${k}_2d.h5" 1e-9
done
# Slabs one cell thick and a hot fluid (a particle moves 0.55 cells a step):
# particles cross whole slabs and land in the far neighbour's straddling
# cells, which takes further rounds of the exchange.
thin=(--set 'system.cells=[8,8,3]' --set srd.temperature=3000 --set run.steps=300 -q)
"$granflow" run "$cooling" "${thin[@]}" -o "$work/one_thin.h5" || fail "one rank (thin) exited with $?"
ranks 3 run "$cooling" "${thin[@]}" -o "$work/ranks3_thin.h5" || fail "3 ranks (thin) exited with $?"
agree "$work/one_thin.h5" "$work/ranks3_thin.h5" 1e-9
# Every observer runs on every rank over its own particles, frames and
# fields included: no round gathers the system onto rank 0, nor does a
# checkpoint.
for run in ranks3_thin ranks2_3d ranks3_2d; do
  no_gather "$work/$run.h5" srd_domain_step observe_srd_state
done
/usr/bin/python3 -c "
import h5py, sys
f = h5py.File('$work/ranks3_3d.h5', 'r')
sys.exit(0 if f['parameters/derived'].attrs['ranks'] == 3 else 'FAIL: ranks not recorded')" && echo "ok: the rank count is recorded" \
  || failures=$((failures + 1))
# No rank holds the whole system: each makes its slab from the start, the
# observers run on every rank over its own particles, the final checkpoint
# is written by rank, and a resumed run reads its slab back by block. Each
# rank's memory beyond a run of 64 cells on as many ranks, at 6.4e5
# particles on 2 ranks, against one process's beyond its run of 64 cells,
# both writing a final checkpoint: 0.56 and 0.50 now; rank 0 was 1.27 when
# it gathered the whole for the checkpoint, 1.1 when it gathered the whole
# to observe, and every rank 1.0 when each built the whole. The same runs
# extended by --resume: 0.50 and 0.38 now; 1.30 and 0.81 when every rank
# read the whole checkpoint and rank 0 gathered it again to write the
# next. 0.8 leaves room for the allocator.
peaks() {  # NP ARGS...
  local np=$1
  shift
  rank_peaks "$np" run "$cooling" --set output.final_checkpoint=true -q --threads 1 -o "$work/memory.h5" "$@"
}
memory=()
for np in 1 2; do
  for cells in '[4,4,4]' '[40,40,40]'; do
    rm -f "$work/memory.h5.checkpoint"
    memory+=("$(peaks "$np" --set "system.cells=$cells" --set run.steps=20)")
    memory+=("$(peaks "$np" --set "system.cells=$cells" --set run.steps=30 --resume)")
  done
done
/usr/bin/python3 - "${memory[@]}" <<'PY' || failures=$((failures + 1))
import sys
def rows(text):
    out = {int(r): (int(kb), int(code)) for r, kb, code in (line.split() for line in text.splitlines())}
    if any(code != 0 for _, code in out.values()): sys.exit(f"FAIL: a memory run exited with {out}")
    return {r: kb for r, (kb, _) in out.items()}
runs = [rows(t) for t in sys.argv[1:9]]
for k, what in ((0, "a run"), (1, "its extension by --resume")):
    small1, whole, small2, split = runs[k], runs[2 + k], runs[4 + k], runs[6 + k]
    growth = whole[0] - small1[0]
    for rank in (0, 1):
        share = (split[rank] - small2[rank]) / growth
        if share > 0.8:
            sys.exit(f"FAIL: in {what}, rank {rank} grows by {share:.2f} of one process's growth: it holds more than "
                     "its slab")
        print(f"ok: in {what}, rank {rank} grows by {share:.2f} of one process's growth "
              f"({(split[rank] - small2[rank]) // 1024} of {growth // 1024} MB)")
PY
ranks 2 run "$cooling" "${three_d[@]}" --threads 1 -o "$work/ranks2_threads1.h5" || fail "2 ranks x 1 thread exited with $?"
agree "$work/ranks2_3d.h5" "$work/ranks2_threads1.h5" 0

# A finished run extended on the same and on another number of ranks.
short=(--set 'system.cells=[8,8,9]' --set run.steps=250 --set output.final_checkpoint=true "${common[@]}")
long=(--set 'system.cells=[8,8,9]' --set run.steps=400 --set output.final_checkpoint=true "${common[@]}")
ranks 2 run "$cooling" "${long[@]}" -o "$work/whole2.h5" || fail "2-rank reference exited with $?"
ranks 3 run "$cooling" "${long[@]}" -o "$work/whole3.h5" || fail "3-rank reference exited with $?"
for k in 2 3; do
  ranks 2 run "$cooling" "${short[@]}" -o "$work/extended$k.h5" || fail "2-rank first part exited with $?"
  ranks "$k" run "$cooling" "${long[@]}" -o "$work/extended$k.h5" --resume || fail "extension on $k ranks exited with $?"
done
agree "$work/whole2.h5" "$work/extended2.h5" 0
agree "$work/whole3.h5" "$work/extended3.h5" 1e-9
# The rounds of a resumed run gather nothing either (the memory check
# above shows that checkpoints are written and read by rank).
no_gather "$work/extended3.h5" srd_domain_step observe_srd_state
/usr/bin/python3 - "$work/extended3.h5" <<'PY' || failures=$((failures + 1))
import sys, h5py
p = h5py.File(sys.argv[1], "r")["provenance"]
ranks = list(p["segments/ranks"][()])
if p.attrs["ranks"] != 3 or ranks != [2, 3]:
    sys.exit(f"FAIL: provenance ranks {p.attrs['ranks']}, segments {ranks} (expected 3 and [2, 3])")
print("ok: provenance records the ranks of each segment: [2, 3]")
PY

# Signals, against one uninterrupted run on 2 ranks (with checkpoints every
# 0.3 s of wall-clock time, which the killed rank resumes from).
big=(--set 'system.cells=[24,24,24]' --set run.steps=1200 -q)
periodic=(--set output.checkpoint_interval=0.3)
ranks 2 run "$cooling" "${big[@]}" "${periodic[@]}" -o "$work/unkilled.h5" || fail "2-rank reference exited with $?"
no_gather "$work/unkilled.h5" srd_domain_step observe_srd_state
# SIGINT to the launcher: every rank stops at the same step and rank 0
# writes the checkpoint; 3 ranks finish the run.
interrupted 2 "$work/cut.h5" run "$cooling" "${big[@]}"
ranks 3 run "$cooling" "${big[@]}" -o "$work/cut.h5" --resume || fail "--resume of the interrupted run on 3 ranks exited with $?"
agree "$work/unkilled.h5" "$work/cut.h5" 1e-9 parameters/toml  # which names the checkpoint interval
# A rank killed outright: the job ends; the last periodic checkpoint resumes.
killed 2 "$work/killed.h5" run "$cooling" "${big[@]}" "${periodic[@]}"
ranks 2 run "$cooling" "${big[@]}" "${periodic[@]}" -o "$work/killed.h5" --resume \
  || fail "--resume after the killed rank exited with $?"
agree "$work/unkilled.h5" "$work/killed.h5" 0
# SIGTERM to one rank alone: the ranks agree on it at the next step.
terminated 2 "$work/termed.h5" run "$cooling" "${big[@]}" "${periodic[@]}"
ranks 2 run "$cooling" "${big[@]}" "${periodic[@]}" -o "$work/termed.h5" --resume \
  || fail "--resume after SIGTERM to one rank exited with $?"
agree "$work/unkilled.h5" "$work/termed.h5" 0

# Between walls, and under Lees-Edwards shear. The energy balance error is
# itself round-off (1e-14 of the energies): it is checked against the
# energies, not compared across runs.
alike() {  # alike NAME SCENARIO ARGS...: on 1, 2 and 3 ranks
  local name="$1" scenario="$2"; shift 2
  "$granflow" run "$scenario" "$@" -q -o "$work/${name}_1.h5" || fail "one rank ($name) exited with $?"
  for k in 2 3; do
    ranks "$k" run "$scenario" "$@" -q -o "$work/${name}_$k.h5" || fail "$k ranks ($name) exited with $?"
    agree "$work/${name}_1.h5" "$work/${name}_$k.h5" 1e-9 observables/energy_balance_error
    no_gather "$work/${name}_$k.h5" srd_domain_step observe_srd_state
  done
}
alike poiseuille_2d "$scenarios/srd_poiseuille.toml" --set run.steps=600 --set poiseuille.warmup_steps=100
alike poiseuille_3d "$scenarios/srd_poiseuille.toml" --set system.dimension=3 --set 'system.cells=[10,8,6]' \
  --set run.steps=300 --set poiseuille.warmup_steps=100
alike shaken_2d "$scenarios/gsrd_shaken.toml" --set system.dimension=2 --set 'system.cells=[48,24]' \
  --set run.steps=600 --set shaken.warmup_steps=100
alike shaken_3d "$scenarios/gsrd_shaken.toml" --set system.dimension=3 --set 'system.cells=[6,8,12]' \
  --set run.steps=300 --set shaken.warmup_steps=100
alike viscosity_2d "$scenarios/srd_viscosity.toml" --set run.steps=1000 --set viscosity.warmup_steps=200 \
  --set output.every_steps=200 --set fields.every_steps=200
alike shear_band_2d "$scenarios/gsrd_shear_band.toml" --set run.steps=800 --set viscosity.warmup_steps=200 \
  --set output.every_steps=200 --set output.positions=all
alike viscosity_3d "$scenarios/srd_viscosity.toml" --set system.dimension=3 --set 'system.cells=[8,8,9]' \
  --set run.steps=600 --set viscosity.warmup_steps=100 --set output.every_steps=100 --set fields.every_steps=200
alike shear_band_3d "$scenarios/gsrd_shear_band.toml" --set system.dimension=3 --set 'system.cells=[6,12,6]' \
  --set run.steps=600 --set viscosity.warmup_steps=100 --set output.every_steps=100
# Extended from 2 ranks on 3: between moving walls with the energy ledger,
# and under shear with the thermostat and the stress sampler, each first
# stopped between two output times (the ledger and the sampler book every
# step: the stop's step once).
extended() {  # extended NAME SCENARIO FIRST_STEPS ARGS...
  local name="$1" scenario="$2" first="$3"; shift 3
  ranks 3 run "$scenario" "$@" --set output.final_checkpoint=true -q -o "$work/${name}_whole.h5" \
    || fail "3-rank reference ($name) exited with $?"
  ranks 2 run "$scenario" "$@" --set output.final_checkpoint=true --set run.steps="$first" -q -o "$work/${name}_ext.h5" \
    || fail "2-rank first part ($name) exited with $?"
  ranks 3 run "$scenario" "$@" --set output.final_checkpoint=true -q -o "$work/${name}_ext.h5" --resume \
    || fail "3-rank extension ($name) exited with $?"
  agree "$work/${name}_whole.h5" "$work/${name}_ext.h5" 1e-9 observables/energy_balance_error
}
extended shaken_2d "$scenarios/gsrd_shaken.toml" 350 --set system.dimension=2 --set 'system.cells=[48,24]' \
  --set run.steps=600 --set shaken.warmup_steps=100
extended viscosity_2d "$scenarios/srd_viscosity.toml" 700 --set run.steps=1000 --set viscosity.warmup_steps=200 \
  --set output.every_steps=200
/usr/bin/python3 - "$work"/shaken_{2d,3d}_{2,3}.h5 <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
for path in sys.argv[1:]:
    o = h5py.File(path, "r")["observables"]
    error = np.max(np.abs(o["energy_balance_error/value"][()]))
    scale = np.max(np.abs(o["kinetic_energy/value"][()])) + np.max(np.abs(o["energy_injected/value"][()]))
    if not error <= 1e-12 * scale:
        sys.exit(f"FAIL: {path}: energy balance error {error:.3g} against energies of {scale:.3g}")
print(f"ok: the energy ledger balances on ranks (to 1e-12 of the energies) in {len(sys.argv) - 1} runs")
PY

# Load balance: a fluid whose density falls off along z (a stored state,
# z -> L (z / L)^2) rebalanced every 50 steps gives the one-rank result to
# round-off, moves the bounds on 3 ranks, and resumes bit for bit across a
# rebalance (the bounds travel in the checkpoint).
"$granflow" run "$cooling" --set 'system.cells=[8,8,24]' --set run.steps=10 --set output.positions=final -q \
  -o "$work/even.h5" || fail "the even state exited with $?"
/usr/bin/python3 "$(dirname "$0")/../../tools/denser_at_one_end.py" "$work/even.h5" "$work/lumpy.h5" \
  || fail "tools/denser_at_one_end.py exited with $?"
lumpy=(--set 'system.cells=[8,8,24]' --set run.steps=300 --set initial.from="$work/lumpy.h5" --set srd.temperature=1
       --set srd.restitution=0.98 --set srd.rotation_angle=10 --set output.positions=all --set fields.every_steps=100
       --set fields.window=10 --set balance.every_steps=50 --set output.final_checkpoint=true)
"$granflow" run "$cooling" "${lumpy[@]}" -q -o "$work/lumpy_1.h5" || fail "one rank (lumpy) exited with $?"
ranks 2 run "$cooling" "${lumpy[@]}" -q -o "$work/lumpy_2.h5" || fail "2 ranks (lumpy) exited with $?"
agree "$work/lumpy_1.h5" "$work/lumpy_2.h5" 1e-9
output=$(ranks 3 run "$cooling" "${lumpy[@]}" -o "$work/lumpy_3.h5" 2>&1) || fail "3 ranks (lumpy) exited with $?"
agree "$work/lumpy_1.h5" "$work/lumpy_3.h5" 1e-9
moved=$(grep -c "the slabs rebalanced" <<< "$output")
[[ $moved -ge 1 ]] && echo "ok: the slabs were rebalanced $moved times on 3 ranks" \
  || fail "the slabs were not rebalanced on 3 ranks: $output"
ranks 3 run "$cooling" "${lumpy[@]}" --set run.steps=100 -q -o "$work/lumpy_ext.h5" || fail "3-rank first part exited with $?"
ranks 3 run "$cooling" "${lumpy[@]}" -q -o "$work/lumpy_ext.h5" --resume || fail "3-rank extension exited with $?"
agree "$work/lumpy_3.h5" "$work/lumpy_ext.h5" 0

# Failed physics on ranks: a particle stranded on the floor of one rank's
# slab stops every rank at the same step with exit 3, the diagnosis said
# once, and the result file marked with it.
output=$(ranks 2 run "$scenarios/gsrd_shaken.toml" -q --set 'system.cells=[8,8,12]' --set run.steps=200 \
  --set shaking.gravity=30 --set shaken.warmup_steps=100 -o "$work/failed.h5md" 2>&1); status=$?
said=$(grep -c "error: the SRD streaming failed" <<< "$output")
if [[ $status -eq 3 && $said -eq 1 ]] && "$granflow" info "$work/failed.h5md" 2>/dev/null | grep -q "stop_reason.*the SRD streaming failed"; then
  echo "ok: failed physics on 2 ranks: exit 3, said once, the file marked"
else
  fail "failed physics on 2 ranks: exit $status, said $said times: $output"
fi

# A velocity that blows up (one particle of a stored start at 1e200): the
# watchdog sees the temperature's totals over the ranks turn infinite, and
# every rank stops at once with exit 3, the diagnosis said once.
with_fast_particle() {  # IN OUT SPEED: IN with particle 7 moving at SPEED along x
  /usr/bin/python3 - "$@" <<'PY' || fail "could not write a state with a fast particle"
import shutil, sys, h5py
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    v = f["particles/all/velocity/value"]
    values = v[()]
    values[-1, 7] = [float(sys.argv[3]), 0.0, 0.0]
    v[...] = values
PY
}
with_fast_particle "$work/even.h5" "$work/blown.h5" 1e200
output=$(ranks 2 run "$cooling" -q --set 'system.cells=[8,8,24]' --set run.steps=20 --set initial.from="$work/blown.h5" \
  -o "$work/blown_run.h5" 2>&1); status=$?
said=$(grep -c "error: the SRD run failed at t = 0 (step 0): the fluid's temperature is not finite" <<< "$output")
if [[ $status -eq 3 && $said -eq 1 ]] && "$granflow" info "$work/blown_run.h5" 2>/dev/null | grep -q "stop_reason.*temperature is not finite"; then
  echo "ok: a non-finite temperature on 2 ranks: exit 3, said once, the file marked"
else
  fail "a non-finite temperature on 2 ranks: exit $status, said $said times: $output"
fi

# The warning of cells clamped at eps_eff = 0 (one fast particle heats its
# cells past the model's range) names the step and the cells of all ranks,
# as on one rank, once.
with_fast_particle "$work/even.h5" "$work/fast.h5" 1e6
hot=(run "$cooling" -q --set 'system.cells=[8,8,24]' --set run.steps=20 --set initial.from="$work/fast.h5")
one=$("$granflow" "${hot[@]}" -o "$work/fast_1.h5" 2>&1 | grep -o "warning: step .* cells (clamped")
for k in 2 3; do
  said=$(ranks "$k" "${hot[@]}" -o "$work/fast_$k.h5" 2>&1 | grep -o "warning: step .* cells (clamped")
  [[ -n "$one" && "$said" == "$one" ]] && echo "ok: on $k ranks the clamped cells are warned of as on one: $said" \
    || fail "clamped cells on $k ranks: '$said', on one rank: '$one'"
done

# Refused, once, with the reason.
refused 'srd.device = "thrust_host"' 2 run "$cooling" --set srd.device=thrust_host
refused "has no distributed step" 2 run "$scenarios/haff_cooling.toml"
refused "cannot split 2 cells along z" 3 run "$cooling" --set 'system.cells=[2,2,2]'
refused "ensemble of independent runs" 2 run "$cooling" --set run.runs=2
# A checkpoint damaged after it was written: rank 0 checks it whole before
# any rank reads its slab, and the resume is refused once.
cp "$work/whole2.h5.checkpoint" "$work/refused.h5.checkpoint"
/usr/bin/python3 -c "
import sys
with open(sys.argv[1], 'r+b') as f:
    f.seek(-4096, 2); byte = f.read(1); f.seek(-4096, 2); f.write(bytes([byte[0] ^ 0x5a]))" "$work/refused.h5.checkpoint"
refused "is not a usable checkpoint" 2 run "$cooling" "${long[@]}" --resume
rm -f "$work/refused.h5.checkpoint"

exit $((failures > 0))
