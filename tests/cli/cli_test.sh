#!/usr/bin/env bash
# Command-line behaviour: bad input exits with status 2 and a message naming
# the problem; a good run writes a complete H5MD file that is identical for
# 1 and 2 threads (haff_cooling, langevin_msd, brownian_edmd); list and info work.
set -u
granflow="$1"
scenario="$2"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0

expect_error() {  # expect_error "what the message must contain" args...
  local needle="$1"; shift
  local output status
  output=$("$granflow" "$@" 2>&1); status=$?
  if [[ $status -ne 2 ]]; then
    echo "FAIL: '$*' exited with $status, expected 2"; echo "$output"; failures=$((failures + 1))
  elif [[ "$output" != *"$needle"* ]]; then
    echo "FAIL: '$*' did not say '$needle':"; echo "$output"; failures=$((failures + 1))
  else
    echo "ok: $* -> $needle"
  fi
}

small=(--set system.count=200 --set run.t_stop=0.5 --set initial.equilibration_collisions=2 -q)
expect_error "unknown configuration key 'system.cuont'" run "$scenario" --set system.cuont=3 -o "$work/x.h5"
expect_error "'system.count' must be an integer" run "$scenario" --set system.count=abc -o "$work/x.h5"
expect_error "'collision.restitution' = 1.5 is out of range: allowed is a number in [0, 1]" \
  run "$scenario" --set collision.restitution=1.5 -o "$work/x.h5"
expect_error "'system.boundary' = 'open' is not allowed: use one of: periodic, reflecting" \
  run "$scenario" --set system.boundary=open -o "$work/x.h5"
expect_error "'system.radius' = -0.1 is out of range" run "$scenario" --set system.radius=-0.1 -o "$work/x.h5"
expect_error "'run.t_stop' = 0 is out of range" run "$scenario" --set run.t_stop=0 -o "$work/x.h5"
expect_error "cannot place 1000 particles at packing fraction" run "$scenario" --set system.radius=0.1 -o "$work/x.h5"
expect_error "must exceed two particle diameters" \
  run "$scenario" --set system.count=1 --set system.radius=0.3 -o "$work/x.h5"
expect_error "configuration file '$work/missing.toml' does not exist" run "$work/missing.toml"
# Misspelt names get the closest known one; a shipped scenario runs by its name from anywhere.
expect_error "did you mean the shipped scenario 'haff_cooling'?" run haff_cooloing
expect_error "did you mean 'collision.restitution'?" run "$scenario" --set colision.restitution=0.5
expect_error "did you mean 'collision.restitution'?" run "$scenario" --set restitution=0.5
expect_error "unknown scenario 'haff_coolin'; did you mean 'haff_cooling'?" keys haff_coolin
expect_error "result file '$work/absent.h5md' does not exist" info "$work/absent.h5md"
expect_error "result file '$work/absent.h5md' does not exist" export "$work/absent.h5md" --format gsd
(cd "$work" && "$granflow" run haff_cooling --set run.t_stop=0.05 -q -o "$work/by_name.h5md") \
  && echo "ok: run haff_cooling by name from another directory" \
  || { echo "FAIL: run haff_cooling by name"; failures=$((failures + 1)); }
# keys FILE shows the file's values, with the default beside those it changes.
printf 'scenario = "haff_cooling"\n[collision]\nrestitution = 0.7\n' > "$work/changed.toml"
"$granflow" keys "$work/changed.toml" | grep -Eq "^collision.restitution +=  ?0.7 .*\(default 0.8\)" \
  && echo "ok: keys FILE shows the file's value and the default" \
  || { echo "FAIL: keys FILE"; "$granflow" keys "$work/changed.toml" | grep restitution; failures=$((failures + 1)); }
printf 'scenario = "no_such_thing"\n' > "$work/unknown.toml"
expect_error "unknown scenario 'no_such_thing'" run "$work/unknown.toml"
srd="$(dirname "$scenario")/srd_viscosity.toml"
expect_error "shear.rate must be > 0" run "$srd" --set shear.rate=0 -o "$work/x.h5"
expect_error "leaves no step to sample" run "$srd" --set run.steps=100 -o "$work/x.h5"
expect_error "system.cells has 3 entries; system.dimension = 2 needs 2" run "$srd" --set 'system.cells=[8,8,8]' -o "$work/x.h5"
channel="$(dirname "$scenario")/srd_poiseuille.toml"
expect_error "axis y has a wall on one side only" run "$channel" --set 'walls=[{axis = "y", side = "lower"}]' -o "$work/x.h5"
expect_error "walls[0].axis = z: the system has 2 dimensions" run "$channel" \
  --set 'walls=[{axis = "z"}, {axis = "z", side = "upper"}]' -o "$work/x.h5"
expect_error "force.acceleration has 3 entries; system.dimension = 2 needs 2" run "$channel" \
  --set 'force.acceleration=[0.01, 0, 0]' -o "$work/x.h5"
expect_error "drives the flow along x" run "$channel" --set 'force.acceleration=[0, 0.01]' -o "$work/x.h5"
shaken="$(dirname "$scenario")/gsrd_shaken.toml"
expect_error "force.slab = [2, 50] leaves the box" run "$shaken" --set 'force.acceleration=[0.1, 0, 0]' \
  --set 'force.slab=[2, 50]' -o "$work/x.h5"
expect_error "force.slab must be [from, to] with from < to" run "$shaken" --set 'force.slab=[3, 1]' -o "$work/x.h5"
expect_error "shaking.amplitude = 15 exceeds a quarter of the height" run "$shaken" --set shaking.amplitude=15 -o "$work/x.h5"
expect_error "thermostat.temperature must be 0" run "$shaken" --set thermostat.temperature=1 -o "$work/x.h5"
# A build without CUDA says so; one with it, on a machine without a driver, says that.
expect_error 'srd.device = "cuda": ' run "$shaken" --set srd.device=cuda -o "$work/x.h5"
bed="$(dirname "$scenario")/shaken_bed.toml"
deep="$(dirname "$scenario")/vibrated_bed.toml"
expect_error "do not fit below the top of the box" run "$bed" --set system.count=100000 -o "$work/x.h5"
expect_error "cannot resolve the sphere-sphere contact" run "$bed" --set run.dt=0.01 -o "$work/x.h5"
expect_error "position Verlet has no rotation" run "$bed" --set contact.friction=0.3 --set run.integrator=position_verlet -o "$work/x.h5"
expect_error "walls[0].position = 50 is outside the box" run "$bed" --set 'walls=[{axis = "z", position = 50}]' -o "$work/x.h5"
expect_error "leaves a compartment narrower than a sphere" run "$bed" --set divider.position=0.5 -o "$work/x.h5"
expect_error "is too short for a periodic axis" run "$deep" --set 'system.box=[3, 24, 80]' -o "$work/x.h5"
expect_error "exceeds the 10580 lattice sites" run "$deep" --set system.count=20000 -o "$work/x.h5"
printf 'scenario = 3\n' > "$work/number.toml"
expect_error "'scenario' must be a scenario name in quotes" run "$work/number.toml"
printf 'scenario = "haff_cooling"\n[system\ncount = 3\n' > "$work/broken.toml"
expect_error "cannot parse" run "$work/broken.toml"
printf 'scenario = "haff_cooling"\n[system]\ncount = 1.5\n' > "$work/float.toml"
expect_error "'system.count' must be an integer, got 1.5" run "$work/float.toml"
expect_error "asks for 1e+15 output times" \
  run "$scenario" --set output.spacing=linear --set output.interval=1e-13 -o "$work/x.h5"
expect_error "'system.radius' = inf is out of range: allowed is a number in (0, inf)" \
  run "$scenario" --set system.radius=inf -o "$work/x.h5"
expect_error "--set expects section.key=value" run "$scenario" --set oops -o "$work/x.h5"
expect_error "--threads: Value 0 not in range" run "$scenario" --threads 0
if [[ -e "$work/x.h5" || -e "$work/x.h5.partial" ]]; then
  echo "FAIL: a failed run left $work/x.h5 or its .partial"; failures=$((failures + 1))
fi
# Values inside the ranges that would never finish are refused up front.
expect_error "would need about" run "$scenario" --set system.count=100 --set system.radius=1e-9 -o "$work/x.h5"
expect_error "output.interval = 1e-09 with run.t_stop = 100 asks for 1e+11 output times" \
  run "$(dirname "$scenario")/speed_distribution.toml" --set output.interval=1e-9 -o "$work/x.h5"
expect_error "output.interval = 1e-308 with run.t_stop = 10 asks for inf output times" \
  run "$(dirname "$scenario")/crater_impact.toml" --set output.interval=1e-308 -o "$work/x.h5"
# The output path is checked before any work.
expect_error "output '$work' is a directory" run "$scenario" "${small[@]}" -o "$work"
expect_error "directory '$work/missing' does not exist" run "$scenario" "${small[@]}" -o "$work/missing/x.h5"
# --set trims spaces and reads 2e2 as an integer.
"$granflow" run "$scenario" --set ' system.count = 2e2 ' --set run.t_stop=0.5 --set initial.equilibration_collisions=2 \
  -q -o "$work/trim.h5" || { echo "FAIL: --set with spaces and 2e2"; failures=$((failures + 1)); }
"$granflow" --version | grep -q '^granflow [0-9]' || { echo "FAIL: --version"; failures=$((failures + 1)); }
# A checkpoint of another configuration is never replaced by a fresh run.
cp "$work/trim.h5" "$work/other.h5.checkpoint"
expect_error "checkpoint '$work/other.h5.checkpoint' of another configuration is in the way" \
  run "$scenario" "${small[@]}" --set collision.restitution=0.5 -o "$work/other.h5"
[[ -e "$work/other.h5.checkpoint" ]] || { echo "FAIL: the other checkpoint was deleted"; failures=$((failures + 1)); }

for threads in 1 2; do
  if ! "$granflow" run "$scenario" "${small[@]}" --threads $threads -o "$work/t$threads.h5"; then
    echo "FAIL: small run with $threads threads"; failures=$((failures + 1))
  fi
done
if [[ -e "$work/t1.h5.partial" ]]; then echo "FAIL: partial file left behind"; failures=$((failures + 1)); fi
info=$("$granflow" info "$work/t1.h5")
for needle in "scenario: haff_cooling" "seed: 1" "/observables/temperature/value" "/profile/system" \
              "/particles/all/position/value" "/particles/all/box/edges"; do
  [[ "$info" == *"$needle"* ]] || { echo "FAIL: info lacks '$needle'"; failures=$((failures + 1)); }
done
if [[ -x /usr/bin/python3 ]] && /usr/bin/python3 -c "import h5py" 2>/dev/null; then
  /usr/bin/python3 - "$work/t1.h5" "$work/t2.h5" <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r") for p in sys.argv[1:])
for name in ("kinetic_energy", "temperature", "collisions_per_particle"):
    x, y = a[f"/observables/{name}/value"][()], b[f"/observables/{name}/value"][()]
    if not np.array_equal(x, y):
        sys.exit(f"FAIL: {name} differs between 1 and 2 threads")
if not np.array_equal(a["/particles/all/position/value"][()], b["/particles/all/position/value"][()]):
    sys.exit("FAIL: positions differ between 1 and 2 threads")
assert list(a["/h5md"].attrs["version"]) == [1, 1]
print("ok: 1 and 2 threads give identical results")
PY
else
  echo "FAIL: /usr/bin/python3 with h5py is needed for the output checks"; failures=$((failures + 1))
fi
expect_error "and system.boundary = \"periodic\"" run "$(dirname "$scenario")/brownian_edmd.toml" \
  --set system.boundary=reflecting -o "$work/x.h5"
expect_error "'system.dimension' = 4 is out of range" run "$(dirname "$scenario")/udsbm_msd.toml" \
  --set system.dimension=4 -o "$work/x.h5"
expect_error "--resume: there is no checkpoint" run "$(dirname "$scenario")/crater_impact.toml" \
  --resume -o "$work/x.h5"
if [[ -e "$work/x.h5" || -e "$work/x.h5.partial" ]]; then
  echo "FAIL: a failed diffusion run left $work/x.h5 or its .partial"; failures=$((failures + 1))
fi

# Frames of a 1D run (an SDE run can be 1D) are refused by every export and
# by initial.from, saying so.
"$granflow" run "$(dirname "$scenario")/langevin_msd.toml" --set system.dimension=1 --set system.count=50 \
  --set run.t_stop=1 --set run.runs=1 --set output.positions=all -q -o "$work/sde1d.h5md"
for format in xyz gsd xdmf mdanalysis; do
  expect_error "holds the frames of a 1D run" export "$work/sde1d.h5md" --format "$format" -o "$work/sde1d.out"
done
expect_error "holds the frames of a 1D run" run "$scenario" --set initial.from="\"$work/sde1d.h5md\"" -o "$work/x.h5"

# SDE and event-driven diffusion runs: the whole output is the same on 1 and 2 threads.
scenarios=$(dirname "$scenario")
for threads in 1 2; do
  "$granflow" run "$scenarios/langevin_msd.toml" --set system.count=20000 --set run.t_stop=1 --set run.runs=2 \
    --set msd.time_average_particles=100 --set output.positions=all --threads $threads -q -o "$work/sde$threads.h5" \
    || { echo "FAIL: langevin_msd with $threads threads"; failures=$((failures + 1)); }
  "$granflow" run "$scenarios/brownian_edmd.toml" --set system.count=300 --set system.radius=0.03 \
    --set run.t_stop=2 --set collision.restitution=0.8 --threads $threads -q -o "$work/edmd$threads.h5" \
    || { echo "FAIL: brownian_edmd with $threads threads"; failures=$((failures + 1)); }
done
/usr/bin/python3 - "$work" <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
work = sys.argv[1]
for run, names in (("sde", ("msd", "msd_stderr", "time_averaged_msd", "ergodicity_breaking")),
                   ("edmd", ("msd", "msd_stderr", "time_averaged_msd"))):
    a, b = (h5py.File(f"{work}/{run}{t}.h5", "r") for t in (1, 2))
    for name in names:
        if not np.array_equal(a[f"/observables/{name}/value"][()], b[f"/observables/{name}/value"][()]):
            sys.exit(f"FAIL: {run} {name} differs between 1 and 2 threads")
a, b = (h5py.File(f"{work}/sde{t}.h5", "r") for t in (1, 2))
for name in ("position", "velocity"):
    if not np.array_equal(a[f"/particles/all/{name}/value"][()], b[f"/particles/all/{name}/value"][()]):
        sys.exit(f"FAIL: langevin_msd frames ({name}) differ between 1 and 2 threads")
print("ok: langevin_msd and brownian_edmd identical on 1 and 2 threads")
PY

# An SDE measurement killed after some of its runs continues from them.
sde_args=(--set run.runs=6 --set run.t_stop=10 --set system.count=2000 --set output.positions=first_last -q)
"$granflow" run "$scenarios/langevin_msd.toml" "${sde_args[@]}" -o "$work/sde_ref.h5"
"$granflow" run "$scenarios/langevin_msd.toml" "${sde_args[@]}" -o "$work/sde_cut.h5" &
pid=$!
for _ in $(seq 1 500); do [[ -e "$work/sde_cut.h5.checkpoint" ]] && break; sleep 0.02; done
kill -9 "$pid" 2>/dev/null; wait "$pid" 2>/dev/null
if [[ ! -e "$work/sde_cut.h5.checkpoint" ]]; then
  echo "FAIL: langevin_msd wrote no checkpoint before it was killed"; failures=$((failures + 1))
else
  "$granflow" run "$scenarios/langevin_msd.toml" "${sde_args[@]}" -o "$work/sde_cut.h5" --resume \
    || { echo "FAIL: langevin_msd --resume"; failures=$((failures + 1)); }
  /usr/bin/python3 - "$work" <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
a, b = (h5py.File(f"{sys.argv[1]}/sde_{n}.h5", "r") for n in ("ref", "cut"))
for name in ("msd", "msd_stderr", "time_averaged_msd", "ergodicity_breaking"):
    if not np.array_equal(a[f"/observables/{name}/value"][()], b[f"/observables/{name}/value"][()]):
        sys.exit(f"FAIL: resumed langevin_msd differs in {name}")
for name in ("position/value", "position/time", "velocity/value", "box/edges/value"):
    if not np.array_equal(a[f"/particles/all/{name}"][()], b[f"/particles/all/{name}"][()]):
        sys.exit(f"FAIL: resumed langevin_msd differs in its first run's frames ({name})")
print("ok: killed and resumed langevin_msd is identical to an uninterrupted run")
PY
fi

# The same for brownian_edmd, whose runs go in parallel.
edmd_args=(--set run.runs=4 --set run.t_stop=10 --set system.count=500 --set system.radius=0.03 -q)
"$granflow" run "$scenarios/brownian_edmd.toml" "${edmd_args[@]}" -o "$work/bd_ref.h5"
"$granflow" run "$scenarios/brownian_edmd.toml" "${edmd_args[@]}" -o "$work/bd_cut.h5" &
pid=$!
for _ in $(seq 1 500); do [[ -e "$work/bd_cut.h5.checkpoint" ]] && break; sleep 0.02; done
kill -9 "$pid" 2>/dev/null; wait "$pid" 2>/dev/null
[[ -e "$work/bd_cut.h5.checkpoint" ]] || { echo "FAIL: brownian_edmd wrote no checkpoint before it was killed"; failures=$((failures + 1)); }
"$granflow" run "$scenarios/brownian_edmd.toml" "${edmd_args[@]}" -o "$work/bd_cut.h5" --resume \
  || { echo "FAIL: brownian_edmd resume"; failures=$((failures + 1)); }
/usr/bin/python3 - "$work" <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
a, b = (h5py.File(f"{sys.argv[1]}/bd_{n}.h5", "r") for n in ("ref", "cut"))
for name in ("msd", "msd_stderr", "time_averaged_msd"):
    if not np.array_equal(a[f"/observables/{name}/value"][()], b[f"/observables/{name}/value"][()]):
        sys.exit(f"FAIL: resumed brownian_edmd differs in {name}")
print("ok: killed and resumed brownian_edmd is identical to an uninterrupted run")
PY

# An interrupted run resumed from its checkpoint gives the same output as an
# uninterrupted one, bit for bit.
long=(--set system.count=30000 --set system.radius=0.008 --set run.t_stop=5 --set output.checkpoint_interval=0
      --set initial.equilibration_collisions=5 -q)
"$granflow" run "$scenario" "${long[@]}" -o "$work/whole.h5" || { echo "FAIL: uninterrupted run"; failures=$((failures + 1)); }
"$granflow" run "$scenario" "${long[@]}" -o "$work/cut.h5" &
pid=$!
for _ in $(seq 100); do [[ -e "$work/cut.h5.checkpoint" ]] && break; sleep 0.05; done
sleep 0.3
kill -9 $pid 2>/dev/null; wait $pid 2>/dev/null
if [[ -e "$work/cut.h5" ]]; then
  echo "FAIL: the run finished before it could be interrupted; make it longer"; failures=$((failures + 1))
else
  [[ -e "$work/cut.h5.checkpoint" ]] || { echo "FAIL: no checkpoint written"; failures=$((failures + 1)); }
  expect_error "other values of keys that change the physics or what was already averaged: run.seed (checkpoint: 1, now: 2)" \
    run "$scenario" "${long[@]}" --set run.seed=2 -o "$work/cut.h5" --resume
  "$granflow" run "$scenario" "${long[@]}" -o "$work/cut.h5" --resume || { echo "FAIL: resume"; failures=$((failures + 1)); }
  [[ -e "$work/cut.h5.checkpoint" ]] && { echo "FAIL: checkpoint left after a finished run"; failures=$((failures + 1)); }
  /usr/bin/python3 - "$work/whole.h5" "$work/cut.h5" <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r") for p in sys.argv[1:])
for name in ("kinetic_energy", "collisions_per_particle"):
    for part in ("step", "time", "value"):
        if not np.array_equal(a[f"/observables/{name}/{part}"][()], b[f"/observables/{name}/{part}"][()]):
            sys.exit(f"FAIL: resumed run differs in {name}/{part}")
for element in ("position", "velocity"):
    if not np.array_equal(a[f"/particles/all/{element}/value"][()], b[f"/particles/all/{element}/value"][()]):
        sys.exit(f"FAIL: resumed run differs in final {element}")
print("ok: interrupted and resumed run is identical to the uninterrupted one")
PY
fi
expect_error "there is no checkpoint" run "$scenario" "${small[@]}" -o "$work/none.h5" --resume

# A second run with the same output is refused at once and leaves the first run's file intact.
"$granflow" run "$scenario" "${long[@]}" -o "$work/same.h5" &
pid=$!
for _ in $(seq 100); do [[ -e "$work/same.h5.partial" ]] && break; sleep 0.02; done
expect_error "output '$work/same.h5' is in use by another run" run "$scenario" "${small[@]}" -o "$work/same.h5"
wait $pid || { echo "FAIL: the first of two runs on one output failed"; failures=$((failures + 1)); }
/usr/bin/python3 - "$work/same.h5" "$work/whole.h5" <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r") for p in sys.argv[1:])
edges = a["/particles/all/box/edges"]
edges = edges["value"][-1].diagonal() if isinstance(edges, h5py.Group) else edges[()]
if a["/parameters/toml"][()] != b["/parameters/toml"][()] or list(edges) != [1, 1, 1]:
    sys.exit("FAIL: the first run's result was damaged by the second")
if not np.array_equal(a["/observables/kinetic_energy/value"][()], b["/observables/kinetic_energy/value"][()]):
    sys.exit("FAIL: the first run's observables differ from an undisturbed run")
print("ok: a concurrent run on the same output is refused and the first run's result is intact")
PY

# A finished run that kept its final state is extended by --resume with a later stop time.
"$granflow" run "$scenario" "${small[@]}" --set output.final_checkpoint=true -o "$work/short.h5" \
  || { echo "FAIL: run keeping its final checkpoint"; failures=$((failures + 1)); }
cp "$work/short.h5" "$work/short_first.h5"
"$granflow" run "$scenario" "${small[@]}" --set run.t_stop=1.5 --resume -o "$work/short.h5" \
  || { echo "FAIL: extending a finished run"; failures=$((failures + 1)); }
"$granflow" run "$scenario" "${small[@]}" --set run.t_stop=1.5 -o "$work/long.h5" \
  || { echo "FAIL: the run to the later stop"; failures=$((failures + 1)); }
# The extension has the output times of one run to t = 1.5: the sample the
# first run took at its stop (t = 0.5, no output time of the longer run) is
# not kept. Up to t = 0.5 it is the first run bit for bit; after it, the one
# run to round-off (the gas is brought to t = 0.5 at the stop, which the one
# run never does: 1e-12 then, 1e-9 at t = 1.5 here).
/usr/bin/python3 - "$work/short_first.h5" "$work/short.h5" "$work/long.h5" <<'PY' || failures=$((failures + 1))
import sys, h5py, numpy as np
first, extended, long = (h5py.File(p, "r")["observables/kinetic_energy"] for p in sys.argv[1:])
t0, t1, t = first["time"][()], extended["time"][()], long["time"][()]
if not (t0[-1] == 0.5 and np.array_equal(t1, t)):
    sys.exit(f"FAIL: extension's times {t1} are not those of one run to 1.5, {t} (first run ends at {t0[-1]})")
before = np.searchsorted(t1, 0.5)
if not np.array_equal(first["value"][:before], extended["value"][:before]):
    sys.exit("FAIL: the extended run does not start with the first run's series")
difference = np.max(np.abs(extended["value"][()] / long["value"][()] - 1))
if not difference < 1e-6:
    sys.exit(f"FAIL: the extension differs from one run to 1.5 by {difference:.3g}")
print(f"ok: a finished run extended from t = 0.5 to 1.5 with --resume is one run to 1.5 (to {difference:.1g})")
PY

# An ensemble stopped by inelastic collapse exits 3 with the diagnosis and leaves no checkpoint behind.
status=0
"$granflow" run "$scenarios/brownian_edmd.toml" --set collision.restitution=0.1 --set collision.contact_time=0 \
  --set run.runs=2 --set system.radius=0.04 --set run.t_stop=50 --set output.checkpoint_interval=0 -q \
  -o "$work/collapse.h5" 2> "$work/collapse.log" || status=$?
if [[ $status -ne 3 ]] || ! grep -q "inelastic collapse" "$work/collapse.log"; then
  echo "FAIL: collapsing brownian_edmd exited $status"; cat "$work/collapse.log"; failures=$((failures + 1))
fi
[[ -e "$work/collapse.h5.checkpoint" ]] && { echo "FAIL: collapsed ensemble left its checkpoint"; failures=$((failures + 1)); }

"$granflow" list | grep -q haff_cooling || { echo "FAIL: list"; failures=$((failures + 1)); }
# A result file whose one-value attribute holds many is refused, not read past its end.
cp "$work/t1.h5" "$work/crafted.h5"
/usr/bin/python3 -c "
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], 'a') as f:
    del f['/parameters/run'].attrs['seed']
    f['/parameters/run'].attrs['seed'] = np.arange(64, dtype=np.int64)
" "$work/crafted.h5"
expect_error "was changed or damaged after it was written" info "$work/crafted.h5"
expect_error "attribute /parameters/run@seed holds 64 values, expected one" info --edited "$work/crafted.h5"
expect_error "is not an HDF5 file" info "$scenario"
# A file without particle frames or fields is refused by export, naming what to change.
"$granflow" run "$scenario" --set output.positions=none --set run.t_stop=0.1 -q -o "$work/none.h5md" || failures=$((failures + 1))
for format in xyz gsd xdmf; do expect_error "output.positions" export "$work/none.h5md" --format "$format"; done

echo "$failures failure(s)"
[[ $failures -eq 0 ]]
