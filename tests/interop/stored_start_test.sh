#!/usr/bin/env bash
# initial.from: haff_cooling started from the final frame of another run
# continues it (positions and velocities at t = 0 identical to the stored
# frame, the same kinetic energy to round-off); started from a GSD file that
# the gsd package itself wrote (a cubic lattice with velocities), its t = 0
# frame is that file's (shifted from HOOMD's centred box, to float
# precision), with the box, count, radius and mass taken over; and stored
# states that cannot start a run are refused with exit 2 and what is wrong:
# overlapping particles, a particle outside a walled box, no velocities, a
# tilted box, a frame that is not there. The soft-sphere beds, an SRD fluid
# and a two-mass mixture continue from their final frames too. Skips (77)
# without the gsd package.
set -u
granflow="$1"
source "$(dirname "$0")/../cli/common.sh"
if ! /usr/bin/python3 -c "import gsd.hoomd" 2> /dev/null; then
  echo "skipped: the gsd package is not installed (apt-get install python3-gsd)"
  exit 77
fi
cd "$work"
"$granflow" run haff_cooling --set run.t_stop=1 -q -o first.h5md || exit 1
"$granflow" run haff_cooling --set initial.from='"first.h5md"' --set run.t_stop=1 --set output.positions=all -q \
  -o second.h5md || exit 1
/usr/bin/python3 - <<'PY' || failures=$((failures + 1))
import sys
import gsd.hoomd
import h5py
import numpy as np
a, b = h5py.File("first.h5md", "r"), h5py.File("second.h5md", "r")
p = "/particles/all/"
same = all(np.array_equal(a[p + n + "/value"][-1], b[p + n + "/value"][0]) for n in ("position", "velocity"))
ea, eb = a["/observables/kinetic_energy/value"][-1], b["/observables/kinetic_energy/value"][0]
print(f"continued from the final frame: positions and velocities identical: {same}; kinetic energy {ea!r} -> {eb!r}")
if not same or abs(ea - eb) > 1e-12 * ea or b[p + "position/time"][0] != 0.0:
    sys.exit("FAIL: the continued run does not start from the stored frame")

# A state written by the gsd package: 512 spheres on a cubic lattice in a box
# of 2, radius 0.05 (diameter 0.1), mass 2, random velocities.
rng = np.random.default_rng(7)
n, length = 512, 2.0
grid = (np.arange(8) + 0.5) * length / 8 - length / 2
position = np.array([[x, y, z] for x in grid for y in grid for z in grid], dtype=np.float32)
frame = gsd.hoomd.Frame() if hasattr(gsd.hoomd, "Frame") else gsd.hoomd.Snapshot()
frame.configuration.box = [length, length, length, 0, 0, 0]
frame.particles.N = n
frame.particles.types = ["A"]
frame.particles.typeid = np.zeros(n, dtype=np.uint32)
frame.particles.position = position
frame.particles.velocity = rng.normal(size=(n, 3)).astype(np.float32)
frame.particles.mass = np.full(n, 2.0, dtype=np.float32)
frame.particles.diameter = np.full(n, 0.1, dtype=np.float32)
with gsd.hoomd.open("lattice.gsd", "wb") as f:
    f.append(frame)
tilted = frame
tilted.configuration.box = [length, length, length, 0.1, 0, 0]
with gsd.hoomd.open("tilted.gsd", "wb") as f:
    f.append(tilted)
PY
"$granflow" run haff_cooling --set initial.from='"lattice.gsd"' --set run.t_stop=0.2 --set output.positions=all -q \
  -o from_gsd.h5md || { echo "FAIL: run from the gsd package's file"; failures=$((failures + 1)); }
/usr/bin/python3 - <<'PY' || failures=$((failures + 1))
import sys
import gsd.hoomd
import h5py
import numpy as np
with gsd.hoomd.open("lattice.gsd", "rb") as t:
    g = t[0]
f = h5py.File("from_gsd.h5md", "r")
p = f["/particles/all"]
x0, v0 = p["position/value"][0], p["velocity/value"][0]
system = f["/parameters/system"].attrs
ok = (np.abs(x0 - (g.particles.position + 1.0)).max() < 1e-6 and np.array_equal(v0, g.particles.velocity.astype(float))
      and system["count"] == 512 and system["box_length"] == 2.0 and abs(system["radius"] - 0.05) < 1e-8
      and system["mass"] == 2.0)  # the diameter is single precision in GSD
print(f"started from the gsd package's file: positions within {np.abs(x0 - (g.particles.position + 1.0)).max():.2g}, "
      f"count {system['count']}, box {system['box_length']}, radius {system['radius']}, mass {system['mass']}")
sys.exit(0 if ok else "FAIL: the run did not start from the GSD frame")
PY

# continues FIRST SECOND: SECOND's first frame is FIRST's last, bit for bit.
continues() {
  /usr/bin/python3 - "$1" "$2" <<'PY' || failures=$((failures + 1))
import sys
import h5py
import numpy as np
a, b = (h5py.File(p, "r") for p in sys.argv[1:3])
p = "/particles/all/"
same = all(np.array_equal(a[p + n + "/value"][-1], b[p + n + "/value"][0]) for n in ("position", "velocity"))
print(f"{sys.argv[2]}: starts from {sys.argv[1]}'s final frame: {same}")
sys.exit(0 if same else "FAIL: not the stored frame")
PY
}

# Soft spheres: a vibrated bed continued from its final frame (periodic
# sideways, images and all), and a shaken bed from its own.
for bed in vibrated_bed shaken_bed; do
  small=(--set system.count=200 --set run.t_stop=0.5 --set output.interval=0.25 --set output.average_after=0.25)
  "$granflow" run $bed "${small[@]}" --set output.positions=all -q -o "$bed.h5md" || exit 1
  "$granflow" run $bed "${small[@]}" --set initial.from="\"$bed.h5md\"" --set output.positions=all -q \
    -o "${bed}_2.h5md" || { echo "FAIL: $bed from its own final frame"; failures=$((failures + 1)); continue; }
  continues "$bed.h5md" "${bed}_2.h5md"
done

# SRD: a granular fluid continued from its final frame (ids, so the same
# order), and a fluid whose count is not a whole number per cell refused.
"$granflow" run gsrd_cooling --set 'system.cells=[8,8,8]' --set run.steps=100 --set output.positions=all -q \
  -o fluid.h5md || exit 1
"$granflow" run gsrd_cooling --set initial.from='"fluid.h5md"' --set run.steps=100 --set output.positions=all -q \
  -o fluid_2.h5md || { echo "FAIL: gsrd_cooling from its own final frame"; failures=$((failures + 1)); }
continues fluid.h5md fluid_2.h5md

# A two-mass mixture continued from its final frame: each particle's species
# and mass as stored (so mass_ratio and heavy_fraction), and the kinetic
# energy at t = 0 that of the stored velocities. A mixture refuses a state
# without species; brownian_edmd (an ensemble of deterministic runs) takes a
# stored state for one run only.
"$granflow" run mixture --set system.count=400 --set mixture.heavy_fraction=0.3 --set mixture.mass_ratio=3 \
  --set output.positions=final -q -o mixture.h5md || exit 1
"$granflow" run mixture --set initial.from='"mixture.h5md"' --set sampling.snapshots=1 --set output.positions=final \
  -q -o mixture_2.h5md || { echo "FAIL: mixture from its own final frame"; failures=$((failures + 1)); }
/usr/bin/python3 - <<'PY' || failures=$((failures + 1))
import sys
import h5py
import numpy as np
a, b = h5py.File("mixture.h5md", "r"), h5py.File("mixture_2.h5md", "r")
p = "/particles/all/"
v, m = a[p + "velocity/value"][-1], a[p + "mass"][()]
stored = 0.5 * np.sum(m[:, None] * v * v) / len(m)  # the observable is per particle
energy = b["/observables/kinetic_energy/value"][0]
mix = b["/parameters/mixture"].attrs
same = np.array_equal(a[p + "species"][()], b[p + "species"][()]) and np.array_equal(m, b[p + "mass"][()])
print(f"mixture continued: species and masses as stored {same}, mass_ratio {mix['mass_ratio']}, heavy_fraction "
      f"{mix['heavy_fraction']}, kinetic energy at t = 0 {energy!r} (stored {stored!r})")
if not same or abs(energy / stored - 1) > 1e-12 or abs(mix["mass_ratio"] - 3) > 1e-12 or abs(mix["heavy_fraction"] - 0.3) > 1e-12:
    sys.exit("FAIL: the mixture did not start from its stored state")
PY
expect_run_refusal() {  # expect_run_refusal "what the message must contain" scenario [--set ...]
  local needle="$1" scenario="$2"; shift 2
  local output status
  output=$("$granflow" run "$scenario" "$@" -o x.h5md 2>&1)
  status=$?
  if [[ $status -eq 2 && "$output" == *"$needle"* ]]; then echo "ok: $scenario $* -> $needle"
  else echo "FAIL: $scenario $*: exit $status: $output"; failures=$((failures + 1)); fi
}
expect_run_refusal "has no particle species" mixture --set initial.from='"first.h5md"'
expect_run_refusal "set run.runs = 1" brownian_edmd --set initial.from='"first.h5md"'
"$granflow" run brownian_edmd --set initial.from='"first.h5md"' --set run.runs=1 --set run.t_stop=0.5 -q \
  -o brownian.h5md || { echo "FAIL: brownian_edmd from a stored state"; failures=$((failures + 1)); }

# States that cannot start a run.
"$granflow" run haff_cooling --set system.boundary='"reflecting"' --set run.t_stop=0.2 -q -o walled.h5md || exit 1
/usr/bin/python3 - <<'PY'
import shutil
import h5py
def edit(source, target, change):
    shutil.copy(source, target)
    with h5py.File(target, "r+") as f:
        change(f["/particles/all"])
def move(particles, i, where):
    x = particles["position/value"]
    frame = x[-1]
    frame[i] = where(frame)
    x[-1] = frame
edit("first.h5md", "overlap.h5md", lambda p: move(p, 7, lambda frame: frame[3] + 0.01))
edit("walled.h5md", "outside.h5md", lambda p: move(p, 5, lambda frame: [1.2, 0.5, 0.5]))
edit("first.h5md", "still.h5md", lambda p: p.__delitem__("velocity"))
PY
expect_refusal() {  # expect_refusal "what the message must contain" file [more --set]
  local needle="$1" file="$2"; shift 2
  local output status
  output=$("$granflow" run haff_cooling --set initial.from="\"$file\"" --set run.t_stop=0.1 "$@" -o x.h5md 2>&1)
  status=$?
  if [[ $status -eq 2 && "$output" == *"$needle"* ]]; then echo "ok: $file $* -> $needle"
  else echo "FAIL: $file $*: exit $status: $output"; failures=$((failures + 1)); fi
}
expect_refusal "particles 3 and 7 overlap" overlap.h5md
expect_refusal "particle 5 at 1.2 along axis 0 is outside the box [0, 1]" outside.h5md
expect_refusal "has no velocities" still.h5md
expect_refusal "the box is tilted" tilted.gsd
expect_refusal "initial.frame = 3: 'first.h5md' holds 1 frames" first.h5md --set initial.frame=3
expect_refusal "initial.from = 'absent.gsd': the file does not exist" absent.gsd
output=$("$granflow" run gsrd_cooling --set initial.from='"first.h5md"' -o x.h5md 2>&1); status=$?
[[ $status -eq 2 && "$output" == *"an SRD box is a whole number"* ]] && echo "ok: SRD from a box of 1 x 1 x 1 refused" \
  || { echo "FAIL: SRD from haff's box: exit $status: $output"; failures=$((failures + 1)); }
echo "$failures failure(s)"
[[ $failures -eq 0 ]]
