#!/usr/bin/env bash
# The SRD device step's source on Thrust's host back end (srd.device =
# "thrust_host") against the CPU systems, through whole scenarios whose
# observers sample every step: srd_viscosity (shear stress), srd_poiseuille
# (profiles, walls, a body force) and gsrd_shaken (granular, a vibrating
# floor, gravity, the energy ledger, profiles, fields). The two follow the
# same trajectory (the device step keeps the CPU's particle order and
# arithmetic), so every series and scalar result must agree; what may differ
# is the order of global sums (fixed blocks on the device, other blocks on
# the CPU), about 1e-16 of each sum per step. Allowed: 1e-9 of the largest
# magnitude of each series (the energy balance error, itself a round-off
# residual, within 1e-12 of the energies it balances). And the state is not copied
# back every step: the device step's downloads (in /profile) are at most one
# per output, while the samplers run every step.
#   device_step_test.sh GRANFLOW
set -u
granflow="$1"
source "$(dirname "$0")/common.sh"
cd "$work"
compare() {  # compare NAME STEPS_SAMPLED MOST_COPIES_BACK ARGS...
  local name="$1" sampled="$2" copies="$3"; shift 3
  for device in cpu thrust_host; do
    "$granflow" run "$name" "$@" --set srd.device="\"$device\"" --profile -q -o "$name-$device.h5md" > /dev/null \
      || { echo "FAIL: $name on $device"; failures=$((failures + 1)); return; }
  done
  /usr/bin/python3 - "$name" "$sampled" "$copies" <<'PY' || failures=$((failures + 1))
import sys
import h5py
import numpy as np
name, sampled, copies = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
a, b = (h5py.File(f"{name}-{d}.h5md", "r") for d in ("cpu", "thrust_host"))
worst, where = 0.0, None
for key, group in a["/observables"].items():
    if not isinstance(group, h5py.Group):
        continue
    x, y = group["value"][()], b[f"/observables/{key}/value"][()]
    if x.shape != y.shape:
        sys.exit(f"FAIL: {name}: {key} has shape {x.shape} on the CPU and {y.shape} on the device step")
    scale = np.nanmax(np.abs(x)) if x.size else 0.0
    allowed = 1e-9
    if key == "energy_balance_error":  # a round-off residual: measured against the energies it balances
        scale = max(np.nanmax(np.abs(a[f"/observables/{k}/value"][()])) for k in ("kinetic_energy", "energy_injected"))
        allowed = 1e-12
    difference = np.nanmax(np.abs(x - y)) / scale if scale > 0 else np.nanmax(np.abs(y))
    if not np.array_equal(np.isnan(x), np.isnan(y)) or difference > allowed:
        sys.exit(f"FAIL: {name}: {key} differs by {difference:.3g} of its largest value (allowed {allowed})")
    if difference > worst:
        worst, where = difference, key
for key, x in a["/observables"].attrs.items():
    y = b["/observables"].attrs[key]
    if isinstance(x, (float, np.floating)) and np.isfinite(x) and abs(x - y) > 1e-9 * max(abs(x), 1e-300):
        sys.exit(f"FAIL: {name}: result {key} = {x} on the CPU, {y} on the device step")
profile = b["/profile"]
calls = dict(zip((s.decode() for s in profile["system"][()]), profile["calls"][()]))
downloads = calls.get("srd_device_step/download", 0)
outputs = a["/observables/temperature/value"].shape[0]
samplers = [s for s in calls if s.startswith("sample_srd")]
on_device = calls.get("srd_device_step/observer_sums", 0)
if not samplers or on_device < sampled - 1 or downloads > copies:
    sys.exit(f"FAIL: {name}: samplers {samplers} ran {[calls[s] for s in samplers]} times, the device summed for "
             f"them {on_device} times, the state was copied back {downloads} times for {outputs} outputs")
print(f"ok: {name}: the device step's series within {worst:.2g} of the CPU's ({where}); {sampled} steps sampled, "
      f"{on_device} summed on the device, {downloads} copies back for {outputs} outputs")
PY
}
compare srd_viscosity 1500 10 --set 'system.cells=[16,16]' --set run.steps=2000 --set viscosity.warmup_steps=500 \
  --set output.every_steps=250
compare srd_poiseuille 1500 10 --set 'system.cells=[20,10]' --set run.steps=2000 --set poiseuille.warmup_steps=500 \
  --set output.every_steps=250
# The fields read the particles in the 10 steps of each window: 5 windows.
compare gsrd_shaken 300 61 --set 'system.cells=[8,8,16]' --set run.steps=500 --set shaken.warmup_steps=200 \
  --set output.every_steps=50 --set fields.every_steps=100
# Failed physics stops the device step as it stops the CPU systems: a
# particle pressed onto the floor by strong gravity needs more than 64
# reflections in one step; both exit 3 at the same step with the same diagnosis.
for device in cpu thrust_host; do
  status=0
  "$granflow" run gsrd_shaken -q --set 'system.cells=[8,8,12]' --set run.steps=200 --set shaking.gravity=30 \
    --set shaken.warmup_steps=100 --set srd.device="\"$device\"" -o "$work/fail-$device.h5md" 2> "$work/fail-$device.log" \
    || status=$?
  if [[ $status -ne 3 ]] || ! grep -q "met the walls more than 64 times in one step" "$work/fail-$device.log"; then
    echo "FAIL: gsrd_shaken under gravity 30 on $device exited $status:"; cat "$work/fail-$device.log"
    failures=$((failures + 1))
  fi
done
if ! diff <(grep -o "failed at t = .*(step [0-9]*)" "$work/fail-cpu.log") \
          <(grep -o "failed at t = .*(step [0-9]*)" "$work/fail-thrust_host.log") > /dev/null; then
  echo "FAIL: the device step failed at another step than the CPU systems"; failures=$((failures + 1))
else
  echo "ok: both stop with exit 3 $(grep -o "failed at t = .*(step [0-9]*)" "$work/fail-cpu.log")"
fi
echo "$failures failure(s)"
[[ $failures -eq 0 ]]
