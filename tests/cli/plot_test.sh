#!/usr/bin/env bash
# tools/plot.py draws one result file and overlays several of one scenario,
# told apart in the legend by the keys whose values differ: two Haff
# cooling runs and two granular SRD cooling runs at two restitutions, and
# ensembles of each (run.runs).
# Skips (exit 77) where /usr/bin/python3 lacks h5py or matplotlib.
set -u
granflow="$1"
source_dir="$2"
source "$(dirname "$0")/common.sh"
if ! /usr/bin/python3 -c "import h5py, matplotlib" 2> /dev/null; then
  echo "skipped: /usr/bin/python3 has no h5py or matplotlib (apt-get install python3-h5py python3-matplotlib)"
  exit 77
fi
fail() { echo "FAIL: $1"; failures=$((failures + 1)); }
plot="$source_dir/tools/plot.py"
haff=(run "$source_dir/scenarios/haff_cooling.toml" -q --set system.count=300 --set run.t_stop=2)
gsrd=(run "$source_dir/scenarios/gsrd_cooling.toml" -q --set 'system.cells=[8,8,8]' --set run.steps=40
      --set fields.every_steps=20 --set fields.window=5 --set output.points_per_decade=5)
for xi in 0.9 0.7; do
  "$granflow" "${haff[@]}" --set collision.restitution=$xi -o "$work/haff_$xi.h5md" || fail "haff_cooling xi = $xi"
  "$granflow" "${gsrd[@]}" --set srd.restitution=$xi -o "$work/gsrd_$xi.h5md" || fail "gsrd_cooling eps = $xi"
done
# Ensembles (run.runs > 1) are drawn as a mean with an error band.
"$granflow" "${haff[@]}" --set run.runs=3 -o "$work/haff_runs.h5md" || fail "haff_cooling run.runs = 3"
"$granflow" "${gsrd[@]}" --set run.runs=2 -o "$work/gsrd_runs.h5md" || fail "gsrd_cooling run.runs = 2"
for figure in "haff_0.9" "haff_0.9 haff_0.7" "gsrd_0.9 gsrd_0.7" "haff_runs haff_0.7" "gsrd_runs"; do
  files=()
  for name in $figure; do files+=("$work/$name.h5md"); done
  out="$work/${figure// /+}.png"
  if /usr/bin/python3 "$plot" "${files[@]}" -o "$out" > /dev/null && [[ -s "$out" ]]; then
    echo "ok: plot.py $figure"
  else
    fail "plot.py $figure wrote no figure"
  fi
done
# The legend of an overlay: the one key that differs, per file.
PYTHONPATH="$source_dir/tools" /usr/bin/python3 - "$work" <<'PY' || fail "overlay labels"
import sys, h5py, plot
work = sys.argv[1]
for stem, key in (("haff", "collision.restitution"), ("gsrd", "srd.restitution")):
    files = [h5py.File(f"{work}/{stem}_{xi}.h5md", "r") for xi in ("0.9", "0.7")]
    labels = plot.overlay_labels(files)
    assert labels == [f"{key} = 0.9", f"{key} = 0.7"], labels
    print("ok: legend", labels)
PY
# The theory figure draws the viscosities the program derives: its formulas
# against a run's derived values (2D and 3D).
"$granflow" run "$source_dir/scenarios/srd_viscosity.toml" -q --set 'system.cells=[8,8]' --set run.steps=20 \
  --set viscosity.warmup_steps=5 --set output.every_steps=10 -o "$work/visc2.h5md" || fail "srd_viscosity 2D"
"$granflow" run "$source_dir/scenarios/srd_viscosity.toml" -q --set system.dimension=3 --set 'system.cells=[6,6,6]' \
  --set srd.rotation_angle=70 --set run.steps=20 --set viscosity.warmup_steps=5 --set output.every_steps=10 \
  -o "$work/visc3.h5md" || fail "srd_viscosity 3D"
PYTHONPATH="$source_dir/tools" /usr/bin/python3 - "$work" <<'PY' || fail "plot.py's SRD viscosities differ from the program's"
import sys, h5py, numpy as np, plot
for name in ("visc2", "visc3"):
    f = h5py.File(f"{sys.argv[1]}/{name}.h5md", "r")
    srd, derived = f["/parameters/srd"].attrs, f["/parameters/derived"].attrs
    d = int(f["/parameters/system"].attrs["dimension"])
    n0, alpha, dt = float(srd["particles_per_cell"]), np.radians(float(srd["rotation_angle"])), float(srd["time_step"])
    temperature = float(f["/parameters/thermostat"].attrs["temperature"]) or float(srd["temperature"])
    kinetic = plot.srd_kinetic_viscosity(d, n0, alpha, temperature, dt)
    collisional = plot.srd_collisional_viscosity(d, n0, alpha, dt)
    assert np.isclose(kinetic, derived["viscosity_kinetic_theory"], rtol=1e-12), (name, kinetic)
    assert np.isclose(collisional, derived["viscosity_collisional_theory"], rtol=1e-12), (name, collisional)
    print(f"ok: {name}: plot.py's viscosities are the program's")
PY
if /usr/bin/python3 "$plot" --srd-viscosity-theory -o "$work/theory.png" > /dev/null && [[ -s "$work/theory.png" ]]; then
  echo "ok: plot.py --srd-viscosity-theory"
else
  fail "plot.py --srd-viscosity-theory wrote no figure"
fi
echo "$failures failure(s)"
[[ $failures -eq 0 ]]
