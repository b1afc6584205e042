#!/usr/bin/env bash
# run.runs of haff_cooling and gsrd_cooling: the ensemble's series are the
# mean, and its <name>_stderr series the standard error of the mean, of the
# same runs a sweep makes as repeats (the same seeds), checked with h5py on
# the sweep's own run files; one run gives the plain run's file (particles
# included), identical to one without run.runs.
# Skips (exit 77) where /usr/bin/python3 lacks h5py.
set -u
granflow="$1"
scenarios=$(realpath "$2")
source "$(dirname "$0")/common.sh"
if ! /usr/bin/python3 -c "import h5py, numpy" 2> /dev/null; then
  echo "skipped: /usr/bin/python3 has no h5py (apt-get install python3-h5py)"
  exit 77
fi
fail() { echo "FAIL: $1"; failures=$((failures + 1)); }

check_against_repeats() {  # name scenario.toml runs observable [--set ...]
  local name="$1" toml="$2" runs="$3" observable="$4"
  shift 4
  "$granflow" run "$toml" -q "$@" --set run.runs="$runs" -o "$work/$name.h5md" || fail "$name: run.runs = $runs exited with $?"
  { echo "scenario_file = \"$toml\""
    echo "output = \"$work/${name}_sweep\""
    echo "repeats = $runs"
    echo "summary = [\"$observable\"]"
    echo "[set]"
    for pair in "$@"; do [[ "$pair" == --set ]] || echo "\"${pair%%=*}\" = ${pair#*=}"; done
  } > "$work/$name.sweep.toml"
  "$granflow" sweep "$work/$name.sweep.toml" -q || fail "$name: the sweep of $runs repeats exited with $?"
  /usr/bin/python3 - "$work/$name.h5md" "$work/${name}_sweep" "$runs" <<'PY' && echo "ok: $name: mean and standard error of $runs runs" || fail "$name: the ensemble does not reduce the repeats"
import glob, sys
import h5py, numpy as np
path, sweep, runs = sys.argv[1], sys.argv[2], int(sys.argv[3])
members = [h5py.File(p, "r") for p in sorted(glob.glob(f"{sweep}/p000_r*.h5md"))]
assert len(members) == runs, f"{len(members)} repeat files"
f = h5py.File(path, "r")
assert "particles" not in f, "an ensemble of several runs has no particle frames"
assert int(f["/observables"].attrs["runs"]) == runs
checked = 0
for name, group in f["/observables"].items():
    if name.endswith("_stderr") or not isinstance(group, h5py.Group) or "value" not in group:
        continue
    values = np.array([m[f"/observables/{name}/value"][()] for m in members])
    assert np.array_equal(group["time"][()], members[0][f"/observables/{name}/time"][()]), name
    mean = values.mean(axis=0)
    error = values.std(axis=0, ddof=1) / np.sqrt(runs)
    scale = np.abs(mean).max() or 1.0
    assert np.allclose(group["value"][()], mean, rtol=1e-12, atol=1e-12 * scale), name
    assert np.allclose(f[f"/observables/{name}_stderr/value"][()], error, rtol=1e-9, atol=1e-12 * scale), name
    unit = group["value"].attrs.get("unit")
    if unit is not None:
        assert f[f"/observables/{name}_stderr/value"].attrs["unit"] == unit, f"{name}_stderr unit"
    checked += 1
assert checked >= 3, f"only {checked} series"
tau0 = np.mean([m["/parameters/derived"].attrs["haff_tau0" if "haff_tau0" in m["/parameters/derived"].attrs else "haff_tau"]
                for m in members])
derived = f["/parameters/derived"].attrs
assert np.isclose(derived["haff_tau0" if "haff_tau0" in derived else "haff_tau"], tau0, rtol=1e-12)
PY
}

haff="$scenarios/haff_cooling.toml"
gsrd="$scenarios/gsrd_cooling.toml"
check_against_repeats haff "$haff" 3 temperature --set system.count=300 --set run.t_stop=2
check_against_repeats gsrd "$gsrd" 2 granular_temperature --set 'system.cells=[6,6,6]' --set run.steps=30 \
  --set fields.every_steps=10 --set fields.window=5 --set output.points_per_decade=4

# One run is the plain run.
"$granflow" run "$haff" -q --set system.count=300 --set run.t_stop=2 --set run.runs=1 -o "$work/one.h5md" \
  || fail "run.runs = 1 exited with $?"
/usr/bin/python3 - "$work/one.h5md" <<'PY' && echo "ok: run.runs = 1 is a plain run" || fail "run.runs = 1 is not a plain run"
import sys, h5py
f = h5py.File(sys.argv[1], "r")
assert "particles" in f and "temperature_stderr" not in f["/observables"]
PY
"$granflow" run "$haff" -q --set run.runs=0 -o "$work/none.h5md" 2> "$work/none.err"
status=$?
[[ $status -eq 2 ]] && grep -q "run.runs" "$work/none.err" && echo "ok: run.runs = 0 refused" \
  || fail "run.runs = 0: exit $status, $(cat "$work/none.err")"

"$granflow" run "$haff" -q --set "initial.from=$work/one.h5md" --set run.runs=2 -o "$work/stored.h5md" 2> "$work/stored.err"
status=$?
[[ $status -eq 2 ]] && grep -q "run.runs = 1" "$work/stored.err" && echo "ok: a stored start with two deterministic runs refused" \
  || fail "a stored start with run.runs = 2: exit $status, $(cat "$work/stored.err")"

[[ $failures -eq 0 ]] && echo "all ensemble checks passed" || { echo "$failures failures"; exit 1; }
