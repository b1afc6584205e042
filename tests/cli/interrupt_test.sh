#!/usr/bin/env bash
# SIGINT stops a run at its next safe point: it exits 130, leaves no result
# file (and no .partial), writes a checkpoint and says how to resume; the
# same command with --resume then gives the same result as an
# uninterrupted run, bit for bit. Event-driven (haff_cooling), an ensemble
# of event-driven runs (brownian_edmd), an SDE ensemble interrupted inside
# its only run (langevin_msd, run.runs = 1, with its frames): their
# observables, and every dataset of the SDE's file. Soft spheres
# (shaken_bed with friction, vibrated_bed) and every SRD scenario, with
# particle frames and fields on: every dataset of the file. A finished
# soft-sphere and SRD run extended with --resume --set run.t_stop / run.steps
# equals one run to the later stop. A run interrupted while its initial
# state is prepared (a long elastic equilibration) stops within seconds,
# exits 130 and leaves nothing behind.
set -u
granflow="$1"
scenarios="$2"
source "$(dirname "$0")/common.sh"

check() {  # check NAME TOML "observables..." ARGS...
  local name="$1" toml="$2" observables="$3"; shift 3
  "$granflow" run "$scenarios/$toml" "$@" -q -o "$work/$name-whole.h5" || { echo "FAIL: $name uninterrupted"; failures=$((failures + 1)); return; }
  local table=()
  [[ -n "${AFTER_START:-}" ]] && table=(--log 1)
  "$granflow" run "$scenarios/$toml" "$@" "${table[@]}" -o "$work/$name-cut.h5" 2> "$work/$name.log" &
  local pid=$!
  if [[ -n "${UNTIL_CHECKPOINT:-}" ]]; then
    # An ensemble writes its checkpoint when a member finishes: waiting for it
    # interrupts the ensemble part-way whatever the machine's speed.
    while kill -0 $pid 2> /dev/null && [[ ! -e "$work/$name-cut.h5.checkpoint" ]]; do sleep 0.05; done
  elif [[ -n "${AFTER_START:-}" ]]; then
    after_stepping_starts "$work/$name.log" "$AFTER_START" $pid
  else
    # Instrumented builds (tests/sanitizers.sh) run several times slower.
    sleep "$(awk -v d="$DELAY" -v s="${GRANFLOW_SLOWDOWN:-1}" 'BEGIN { print d * s }')"
  fi
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
  same_result "$work/$name-whole.h5" "$work/$name-cut.h5" $observables
}

# same_result WHOLE RESUMED [observables...]: the named observables equal,
# or with none named, every dataset (provenance and timings aside).
same_result() {
  /usr/bin/python3 - "$@" <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r") for p in sys.argv[1:3])
names = sys.argv[3:]
if names:
    paths = [f"observables/{n}" + ("" if isinstance(a[f"observables/{n}"], h5py.Dataset) else f"/{part}")
             for n in names for part in ("step", "time", "value")]
else:
    paths = []
    a.visititems(lambda n, o: paths.append(n) if isinstance(o, h5py.Dataset) and not n.startswith(("provenance", "profile")) else None)
    extra = []
    b.visititems(lambda n, o: extra.append(n) if isinstance(o, h5py.Dataset) and not n.startswith(("provenance", "profile")) and n not in a else None)
    if extra: sys.exit(f"FAIL: {sys.argv[2]} has datasets the uninterrupted run has not: {extra}")
for path in dict.fromkeys(paths):
    if path not in b: sys.exit(f"FAIL: {sys.argv[2]} lacks {path}")
    x, y = np.asarray(a[path][()]), np.asarray(b[path][()])
    # A one-run ensemble's standard errors are NaN in both.
    same = np.array_equal(x, y, equal_nan=np.issubdtype(x.dtype, np.floating))
    if x.shape != y.shape or not same:
        sys.exit(f"FAIL: resumed {path} differs from the uninterrupted run ({x.shape} and {y.shape})")
assert "/profile/system" in b, "no /profile"
print(f"ok: {sys.argv[2]} equals the uninterrupted run in {len(paths) if names else 'every'} dataset(s)")
PY
}

AFTER_START=0.4 check haff haff_cooling.toml "kinetic_energy temperature collisions_per_particle" \
  --set system.count=30000 --set system.radius=0.005 --set run.t_stop=10 --set initial.equilibration_collisions=5
UNTIL_CHECKPOINT=1 check brownian brownian_edmd.toml "msd msd_stderr time_averaged_msd ergodicity_breaking" \
  --set run.runs=4 --set run.t_stop=300 --set system.count=500 --set system.radius=0.03
DELAY=1 check langevin langevin_msd.toml "" \
  --set run.runs=1 --set run.t_stop=20 --set system.count=100000 --set msd.time_average_particles=200 \
  --set output.positions=first_last
# Soft spheres and SRD: every dataset, particle frames and fields included.
AFTER_START=0.4 check shaken shaken_bed.toml "" \
  --set run.t_stop=10 --set output.average_after=4 --set contact.friction=0.5 --set output.positions=all
AFTER_START=0.4 check vibrated vibrated_bed.toml "" --set system.count=4000 --set run.t_stop=8 --set output.interval=0.5 \
  --set output.average_after=1 --set output.positions=all
AFTER_START=0.4 check gsrd_cooling gsrd_cooling.toml "" --set 'system.cells=[16,16,16]' --set run.steps=1200 \
  --set fields.every_steps=100 --set output.positions=first_last
# An ensemble of three (two cores): interrupted while its third run goes on,
# the two finished ones come back from the checkpoint, their units with them.
UNTIL_CHECKPOINT=1 check gsrd_ensemble gsrd_cooling.toml "" --set 'system.cells=[16,16,16]' --set run.steps=1000 \
  --set run.runs=3 --threads 2
/usr/bin/python3 - "$work/gsrd_ensemble-whole.h5" "$work/gsrd_ensemble-cut.h5" <<'PY' || failures=$((failures + 1))
import sys, h5py
a, b = (h5py.File(p, "r") for p in sys.argv[1:])
units = lambda f: {n: f[f"observables/{n}/value"].attrs.get("unit") for n in f["observables"] if "value" in f[f"observables/{n}"]}
assert units(a) == units(b) and units(a)["temperature_stderr"] == units(a)["temperature"], (units(a), units(b))
print("ok: the resumed ensemble keeps every series' unit")
PY
AFTER_START=0.4 check gsrd_shaken gsrd_shaken.toml "" --set 'system.cells=[8,8,40]' --set run.steps=600 \
  --set shaken.warmup_steps=200 --set fields.every_steps=100 --set fields.window=20 --set output.positions=all
AFTER_START=0.4 check srd_viscosity srd_viscosity.toml "" --set run.steps=4000 --set viscosity.warmup_steps=1000 \
  --set fields.every_steps=500 --set output.positions=first_last
AFTER_START=0.4 check srd_poiseuille srd_poiseuille.toml "" --set run.steps=3000 --set poiseuille.warmup_steps=500 \
  --set fields.every_steps=500 --set output.positions=first_last

# A finished run extends: the same result as one run to the later stop.
extend() {  # extend NAME TOML STOP_KEY FIRST SECOND ARGS...
  local name="$1" toml="$2" key="$3" first="$4" second="$5"; shift 5
  "$granflow" run "$scenarios/$toml" "$@" --set "$key=$second" --set output.final_checkpoint=true -q \
    -o "$work/$name-whole.h5" &&
    "$granflow" run "$scenarios/$toml" "$@" --set "$key=$first" --set output.final_checkpoint=true -q \
      -o "$work/$name-ext.h5" &&
    "$granflow" run "$scenarios/$toml" "$@" --set "$key=$second" --set output.final_checkpoint=true -q \
      -o "$work/$name-ext.h5" --resume || { echo "FAIL: $name extension"; failures=$((failures + 1)); return; }
  same_result "$work/$name-whole.h5" "$work/$name-ext.h5"
}
extend shaken_ext shaken_bed.toml run.t_stop 4 8 --set output.average_after=2 --set output.positions=all
extend cooling_ext gsrd_cooling.toml run.steps 500 1000 --set 'system.cells=[16,16,16]' --set fields.every_steps=100

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
