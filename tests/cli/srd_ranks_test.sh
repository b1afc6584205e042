#!/usr/bin/env bash
# One SRD system over MPI ranks (`mpirun -np K granflow run`, a
# -DGRANFLOW_MPI=ON build; systems/srd/srd_domain_step.hpp):
#  - gsrd_cooling in 3D and 2D on 2 and 3 ranks gives the one-rank result,
#    with particle frames and fields: the same cells, particles and random
#    numbers, the straddling cells' sums in another order, so every dataset
#    agrees to round-off (measured 1e-12 of its largest value; checked at
#    1e-9), and integer ones exactly;
#  - on a given number of ranks the result does not depend on the threads;
#  - a finished 2-rank run extended with --resume on 2 ranks equals one
#    2-rank run bit for bit, and extended on 3 ranks equals a 3-rank run to
#    round-off;
#  - SIGINT to mpirun (which sends the ranks SIGTERM) stops every rank at
#    one step with a checkpoint and no result file, and --resume on 3 ranks
#    finishes it; a rank killed with
#    SIGKILL ends the job, and --resume from the last periodic checkpoint
#    gives the uninterrupted result bit for bit;
#  - what is not distributed is refused once, on rank 0, with exit status 2.
set -u
granflow="$1"
mpiexec="$2"
scenarios="$3"
source "$(dirname "$0")/common.sh"
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
ranks() { local n="$1"; shift; "$mpiexec" -np "$n" --oversubscribe --bind-to none "$granflow" "$@"; }

# agree A B TOLERANCE: every dataset but provenance and timings, floats within
# TOLERANCE of the dataset's largest magnitude (0: bit for bit), others equal.
agree() {
  /usr/bin/python3 - "$@" <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r") for p in sys.argv[1:3])
tolerance = float(sys.argv[3])
paths, worst = [], 0.0
a.visititems(lambda n, o: paths.append(n) if isinstance(o, h5py.Dataset) and not n.startswith(("provenance", "profile")) else None)
for path in paths:
    if path not in b: sys.exit(f"FAIL: {sys.argv[2]} lacks {path}")
    x, y = np.asarray(a[path][()]), np.asarray(b[path][()])
    if x.shape != y.shape: sys.exit(f"FAIL: {path}: shapes {x.shape} and {y.shape}")
    if tolerance > 0 and np.issubdtype(x.dtype, np.floating):
        scale = np.nanmax(np.abs(x)) if x.size and not np.all(np.isnan(x)) else 0.0
        gap = np.nanmax(np.abs(x - y)) if x.size and not np.all(np.isnan(x)) else 0.0
        if not np.array_equal(np.isnan(x), np.isnan(y)) or gap > tolerance * max(scale, 1e-300):
            sys.exit(f"FAIL: {path} differs by {gap:.3g} (largest value {scale:.3g}) between {sys.argv[1]} and {sys.argv[2]}")
        if scale > 0: worst = max(worst, gap / scale)
    elif not np.array_equal(x, y, equal_nan=np.issubdtype(x.dtype, np.floating)):
        sys.exit(f"FAIL: {path} differs between {sys.argv[1]} and {sys.argv[2]}")
print(f"ok: {sys.argv[2]} agrees with {sys.argv[1]} in {len(paths)} datasets "
      + (f"(largest relative difference {worst:.2g})" if tolerance > 0 else "(bit for bit)"))
PY
}

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
/usr/bin/python3 -c "
import h5py, sys
f = h5py.File('$work/ranks3_3d.h5', 'r')
sys.exit(0 if f['parameters/derived'].attrs['ranks'] == 3 else 'FAIL: ranks not recorded')" && echo "ok: the rank count is recorded" \
  || failures=$((failures + 1))
ranks 2 run "$cooling" "${three_d[@]}" --threads 1 -o "$work/ranks2_threads1.h5" || fail "2 ranks x 1 thread exited with $?"
agree "$work/ranks2_3d.h5" "$work/ranks2_threads1.h5" 0

# A finished run extended on the same and on another number of ranks.
short=(--set 'system.cells=[8,8,9]' --set run.steps=200 --set output.final_checkpoint=true "${common[@]}")
long=(--set 'system.cells=[8,8,9]' --set run.steps=400 --set output.final_checkpoint=true "${common[@]}")
ranks 2 run "$cooling" "${long[@]}" -o "$work/whole2.h5" || fail "2-rank reference exited with $?"
ranks 3 run "$cooling" "${long[@]}" -o "$work/whole3.h5" || fail "3-rank reference exited with $?"
for k in 2 3; do
  ranks 2 run "$cooling" "${short[@]}" -o "$work/extended$k.h5" || fail "2-rank first part exited with $?"
  ranks "$k" run "$cooling" "${long[@]}" -o "$work/extended$k.h5" --resume || fail "extension on $k ranks exited with $?"
done
agree "$work/whole2.h5" "$work/extended2.h5" 0
agree "$work/whole3.h5" "$work/extended3.h5" 1e-9

# SIGINT to the launcher: every rank stops at the same step and rank 0
# writes the checkpoint; 3 ranks finish the run. The launcher starts with
# SIGINT handled as from a terminal: a script's background job inherits it
# ignored (or blocked), and mpirun keeps it so.
big=(--set 'system.cells=[24,24,24]' --set run.steps=3000 -q)
/usr/bin/python3 -c 'import os, signal, sys
signal.signal(signal.SIGINT, signal.SIG_DFL)
signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
os.execvp(sys.argv[1], sys.argv[1:])' \
  "$mpiexec" -np 2 --oversubscribe --bind-to none "$granflow" run "$cooling" "${big[@]}" -o "$work/cut.h5" \
  > "$work/cut.log" 2>&1 &
launcher=$!
for _ in $(seq 1 1500); do [[ -e "$work/cut.h5.partial" ]] && break; sleep 0.02; done
sleep 2
kill -INT "$launcher"
wait "$launcher"; status=$?
if [[ $status -ne 0 && -e "$work/cut.h5.checkpoint" && ! -e "$work/cut.h5" && ! -e "$work/cut.h5.partial" ]] \
   && [[ $(grep -c "interrupted (signal" "$work/cut.log") -eq 1 ]]; then
  echo "ok: SIGINT stopped the ranks with one checkpoint and one message (mpirun exit $status)"
else
  fail "SIGINT: exit $status, files: $(ls "$work" | grep '^cut' | tr '\n' ' '), log: $(cat "$work/cut.log")"
fi
ranks 3 run "$cooling" "${big[@]}" -o "$work/cut.h5" --resume || fail "--resume of the interrupted run on 3 ranks exited with $?"
ranks 3 run "$cooling" "${big[@]}" -o "$work/uncut.h5" || fail "3-rank uninterrupted run exited with $?"
agree "$work/uncut.h5" "$work/cut.h5" 1e-9

# A rank killed outright: the job ends; the last periodic checkpoint resumes.
ranks 2 run "$cooling" "${big[@]}" --set output.checkpoint_interval=1 -o "$work/killed.h5" > "$work/killed.log" 2>&1 &
launcher=$!
for _ in $(seq 1 1500); do [[ -e "$work/killed.h5.checkpoint" ]] && break; sleep 0.02; done
victim=$(pgrep -n -f "^$granflow run $cooling .*-o $work/killed.h5")
[[ -n "$victim" ]] && kill -9 "$victim"
wait "$launcher"; status=$?
[[ $status -ne 0 && -e "$work/killed.h5.checkpoint" ]] && echo "ok: a killed rank ended the job (mpirun exit $status)" \
  || fail "killed rank: exit $status, files: $(ls "$work" | grep '^killed' | tr '\n' ' ')"
ranks 2 run "$cooling" "${big[@]}" --set output.checkpoint_interval=1 -o "$work/killed.h5" --resume \
  || fail "--resume after the killed rank exited with $?"
ranks 2 run "$cooling" "${big[@]}" --set output.checkpoint_interval=1 -o "$work/unkilled.h5" || fail "2-rank reference exited with $?"
agree "$work/unkilled.h5" "$work/killed.h5" 0

# Refused, once, with the reason.
refused() {  # refused PATTERN RANKS ARGS...
  local pattern="$1"; shift
  local output status
  output=$(ranks "$@" -q -o "$work/refused.h5" 2>&1); status=$?
  local said; said=$(grep -c "$pattern" <<< "$output")
  if [[ $status -ne 0 && $said -eq 1 && ! -e "$work/refused.h5" ]]; then echo "ok: refused once: $pattern"
  else fail "expected one refusal '$pattern' (exit $status, said $said times): $output"; fi
}
refused "shear.rate = " 2 run "$scenarios/srd_viscosity.toml"
refused "between walls" 2 run "$scenarios/gsrd_shaken.toml"
refused "has no distributed step" 2 run "$scenarios/haff_cooling.toml"
refused "cannot split 2 cells" 3 run "$cooling" --set 'system.cells=[8,8,2]'
refused "ensemble of independent runs" 2 run "$cooling" --set run.runs=2

exit $((failures > 0))
