#!/usr/bin/env bash
# SIGINT stops a run at its next safe point: it exits 130, leaves no result
# file (and no .partial), writes a checkpoint and says how to resume; the
# same command with --resume then gives the same observables as an
# uninterrupted run, bit for bit. One event-driven run (haff_cooling), one
# ensemble of event-driven runs (brownian_edmd), one SDE ensemble
# interrupted inside its only run (langevin_msd, run.runs = 1) and one
# soft-sphere run with friction (shaken_bed: neighbour lists reordering the
# spheres, the contacts' springs, the compartment counts and the
# time-averaged profiles all cross the checkpoint). A run
# interrupted while its initial state is prepared (a long elastic
# equilibration) stops within seconds, exits 130 and leaves nothing behind.
set -u
granflow="$1"
scenarios="$2"
source "$(dirname "$0")/common.sh"

check() {  # check NAME TOML "observables..." ARGS...
  local name="$1" toml="$2" observables="$3"; shift 3
  "$granflow" run "$scenarios/$toml" "$@" -q -o "$work/$name-whole.h5" || { echo "FAIL: $name uninterrupted"; failures=$((failures + 1)); return; }
  "$granflow" run "$scenarios/$toml" "$@" -o "$work/$name-cut.h5" 2> "$work/$name.log" &
  local pid=$!
  # Instrumented builds (tests/sanitizers.sh) run several times slower.
  sleep "$(awk -v d="$DELAY" -v s="${GRANFLOW_SLOWDOWN:-1}" 'BEGIN { print d * s }')"
  kill -INT $pid
  wait $pid; local status=$?
  if [[ $status -ne 130 ]]; then
    echo "FAIL: $name interrupted exited with $status, expected 130 (raise its size if it finished first)"; cat "$work/$name.log"
    failures=$((failures + 1)); return
  fi
  [[ -e "$work/$name-cut.h5" || -e "$work/$name-cut.h5.partial" ]] && { echo "FAIL: $name left a result file"; failures=$((failures + 1)); }
  [[ -e "$work/$name-cut.h5.checkpoint" ]] || { echo "FAIL: $name wrote no checkpoint"; failures=$((failures + 1)); return; }
  grep -q -- "--resume" "$work/$name.log" || { echo "FAIL: $name did not say how to resume"; failures=$((failures + 1)); }
  "$granflow" run "$scenarios/$toml" "$@" -q -o "$work/$name-cut.h5" --resume || { echo "FAIL: $name --resume"; failures=$((failures + 1)); return; }
  /usr/bin/python3 - "$work/$name-whole.h5" "$work/$name-cut.h5" $observables <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r") for p in sys.argv[1:3])
for name in sys.argv[3:]:
    if isinstance(a[f"/observables/{name}"], h5py.Dataset):  # time-independent
        if not np.array_equal(a[f"/observables/{name}"][()], b[f"/observables/{name}"][()]):
            sys.exit(f"FAIL: resumed {name} differs from the uninterrupted run")
        continue
    for part in ("step", "time", "value"):
        x, y = a[f"/observables/{name}/{part}"][()], b[f"/observables/{name}/{part}"][()]
        if not np.array_equal(x, y):
            sys.exit(f"FAIL: resumed {name}/{part} differs from the uninterrupted run")
assert "/profile/system" in b, "no /profile"
print(f"ok: {sys.argv[2]} interrupted and resumed equals the uninterrupted run")
PY
}

DELAY=1.5 check haff haff_cooling.toml "kinetic_energy temperature collisions_per_particle" \
  --set system.count=60000 --set system.radius=0.0064 --set run.t_stop=40 --set initial.equilibration_collisions=5
DELAY=1.5 check brownian brownian_edmd.toml "msd msd_stderr time_averaged_msd ergodicity_breaking" \
  --set run.runs=4 --set run.t_stop=300 --set system.count=500 --set system.radius=0.03
DELAY=1.5 check langevin langevin_msd.toml "msd time_averaged_msd ergodicity_breaking" \
  --set run.runs=1 --set run.t_stop=20 --set system.count=200000 --set msd.time_average_particles=200
DELAY=2 check shaken shaken_bed.toml \
  "asymmetry kinetic_energy elastic_energy energy_dissipated flux_left_to_right packing_fraction_profile_mean_left temperature_profile_mean_right" \
  --set run.t_stop=60 --set output.average_after=10 --set contact.friction=0.5

preparing() {  # preparing NAME TOML ARGS...: SIGINT during the preparation
  local name="$1" toml="$2"; shift 2
  "$granflow" run "$scenarios/$toml" "$@" -o "$work/$name.h5" 2> "$work/$name.log" &
  local pid=$! started=$SECONDS
  sleep "$(awk -v s="${GRANFLOW_SLOWDOWN:-1}" 'BEGIN { print 1.5 * s }')"
  kill -INT $pid
  wait $pid; local status=$? took=$((SECONDS - started))
  if [[ $status -ne 130 ]] || ! grep -q "while preparing the initial state" "$work/$name.log"; then
    echo "FAIL: $name interrupted during its preparation exited with $status"; cat "$work/$name.log"
    failures=$((failures + 1))
  elif (( took > 10 * ${GRANFLOW_SLOWDOWN:-1} )); then
    echo "FAIL: $name took ${took} s to stop after SIGINT during its preparation"; failures=$((failures + 1))
  elif ls "$work/$name".h5* > /dev/null 2>&1; then
    echo "FAIL: $name left files after an interrupted preparation: $(ls "$work/$name".h5*)"; failures=$((failures + 1))
  else echo "ok: $name stopped during its preparation"; fi
}
# Each would prepare for minutes: equilibrating 10^5 spheres for 2000 collisions
# per particle, melting a bed of 10^5 disks for 2000.
preparing equilibration haff_cooling.toml --set system.count=100000 --set system.radius=0.004 \
  --set initial.equilibration_collisions=2000
preparing melting crater_impact.toml --set system.count=100000 --set bed.melt_collisions=2000

echo "$failures failure(s)"
[[ $failures -eq 0 ]]
