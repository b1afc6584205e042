#!/usr/bin/env bash
# The time-stepped methods (soft spheres, SRD, SDE) when their input or their
# physics goes wrong: bad values stop with exit 2 and a message naming the
# key, a blow-up stops with exit 3 and a diagnosis, and nothing hangs,
# crashes or grows without bound. One check per class of failure.
set -u
granflow="$1"
scenarios="$2"
source "$(dirname "$0")/common.sh"
bed="$scenarios/shaken_bed.toml"
deep="$scenarios/vibrated_bed.toml"
tiny=(--set system.count=50 --set run.t_stop=2 --set output.average_after=1 -q)

# expect_status STATUS "what the message must contain" args... (each run at most 60 s)
expect_status() {
  local want="$1" needle="$2"; shift 2
  local output status
  output=$(timeout 60 "$granflow" "$@" 2>&1); status=$?
  if [[ $status -ne $want ]]; then
    echo "FAIL: '$*' exited with $status, expected $want"; echo "$output" | tail -5; failures=$((failures + 1))
  elif [[ "$output" != *"$needle"* ]]; then
    echo "FAIL: '$*' did not say '$needle':"; echo "$output" | tail -5; failures=$((failures + 1))
  else
    echo "ok: exit $want: $needle"
  fi
}

# Peak resident memory (kB) of one run.
peak_rss() {
  /usr/bin/python3 -c 'import resource, subprocess, sys
subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)' "$@"
}

# Memory does not grow with the length of a run, on one thread as on two.
for threads in 1 2; do
  short=$(peak_rss "$granflow" run "$bed" --set run.t_stop=10 --set output.average_after=1 --threads $threads -q \
    -o "$work/short.h5md")
  long=$(peak_rss "$granflow" run "$bed" --set run.t_stop=40 --set output.average_after=1 --threads $threads -q \
    -o "$work/long.h5md")
  # Outputs and averages add a few kB per time unit; a leak per step adds MBs.
  if (( long > short + short / 5 + 4096 )); then
    echo "FAIL: shaken_bed on $threads thread(s): peak RSS $short kB to t = 10, $long kB to t = 40"
    failures=$((failures + 1))
  else
    echo "ok: shaken_bed on $threads thread(s): peak RSS $short kB to t = 10, $long kB to t = 40"
  fi
done

# Bad input: exit 2, the key named, before any step.
expect_status 2 "contact.stiffness = 2e+04 is too soft for this run" run "$bed" "${tiny[@]}" \
  --set 'gravity.acceleration=[0,0,-1e6]' -o "$work/x.h5md"
expect_status 2 "run.dt = 0.1 cannot resolve the sphere-sphere contact" run "$bed" "${tiny[@]}" \
  --set 'contact.model="hertz"' --set run.dt=0.1 -o "$work/x.h5md"
expect_status 2 "cannot resolve the walls[4] contact (walls[4].stiffness = 1e+12)" run "$bed" "${tiny[@]}" --set run.dt=0.0003 \
  --set 'walls=[{axis="x",position=0.0},{axis="x",position=20.0},{axis="y",position=0.0},{axis="y",position=4.0},{axis="z",position=0.0,stiffness=1e12},{axis="z",position=40.0}]' \
  -o "$work/x.h5md"
expect_status 2 "'contact.restitution' = 0 is out of range: allowed is a number in (0, 1]" run "$bed" "${tiny[@]}" \
  --set contact.restitution=0 -o "$work/x.h5md"
expect_status 2 "contact.damping_rate = 130.0: the sphere-sphere contact is overdamped" run "$deep" -q \
  --set contact.damping_rate=130 -o "$work/x.h5md"
expect_status 2 "particle.mass = 1e+308 and contact.stiffness = 2e+04 give the sphere-sphere contact no time scale" \
  run "$bed" "${tiny[@]}" --set particle.mass=1e308 -o "$work/x.h5md"
expect_status 2 "shaking.frequency = inf: the wall's speed is not finite" run "$bed" "${tiny[@]}" \
  --set shaking.frequency=1e308 -o "$work/x.h5md"
expect_status 2 "output.interval = 4.941e-324 is shorter than the time step" run "$bed" "${tiny[@]}" \
  --set output.interval=5e-324 -o "$work/x.h5md"
expect_status 2 "bed.lattice_density = 1e+308 over bed.fill gives inf lattice sites" run "$deep" -q \
  --set bed.lattice_density=1e308 -o "$work/x.h5md"
expect_status 2 "layers of spheres of particle.radius = 1e-100" run "$deep" -q --set particle.radius=1e-100 -o "$work/x.h5md"
expect_status 2 "walls: the box is closed along x but has no wall on its lower side" run "$bed" "${tiny[@]}" \
  --set 'walls=[{axis="z",position=0.0,amplitude=0.5,frequency=2.5}]' -o "$work/x.h5md"
expect_status 2 "the walls leave sphere 0 of the initial state outside them (z = " run "$bed" "${tiny[@]}" \
  --set 'walls=[{axis="x",position=0.0},{axis="x",position=20.0},{axis="y",position=0.0},{axis="y",position=4.0},{axis="z",position=10.0},{axis="z",position=40.0}]' \
  -o "$work/x.h5md"
expect_status 2 "system.box = [1.5, 1.5, 1.5] is too small" run "$bed" "${tiny[@]}" --set 'system.box=[1.5,1.5,1.5]' \
  -o "$work/x.h5md"
expect_status 2 "shaking.amplitude = 1e+308 exceeds a quarter of the box height" run "$bed" "${tiny[@]}" \
  --set shaking.amplitude=1e308 -o "$work/x.h5md"
channel="$scenarios/srd_poiseuille.toml"
expect_status 2 "srd.time_step = 1000 lets a fast particle" run "$channel" -q --set 'system.cells=[8,8]' \
  --set srd.time_step=1000 -o "$work/x.h5md"
expect_status 2 "shear.rate = 0.02 with walls" run "$channel" -q --set shear.rate=0.02 -o "$work/x.h5md"
expect_status 2 "srd.time_step = 1e+308 moves a fast particle" run "$scenarios/gsrd_cooling.toml" -q \
  --set srd.time_step=1e308 -o "$work/x.h5md"
expect_status 2 "a double cannot hold" run "$scenarios/srd_viscosity.toml" -q --set thermostat.temperature=1e308 \
  -o "$work/x.h5md"

# A key that shaped what was already averaged may not change on resume.
"$granflow" run "$bed" "${tiny[@]}" --set output.final_checkpoint=true -o "$work/avg.h5md" \
  || { echo "FAIL: shaken_bed with a final checkpoint"; failures=$((failures + 1)); }
expect_status 2 "output.average_after (checkpoint: 1.0, now: 1.5)" run "$bed" "${tiny[@]}" \
  --set output.final_checkpoint=true --set output.average_after=1.5 --set run.t_stop=3 -o "$work/avg.h5md" --resume

# What the pre-checks let through runs to a sane end: a huge, empty box
# (the cell grid is bounded), restitution near 0 (the step follows the dashpot).
for extreme in 'system.box=[1e9,4,40]' contact.restitution=1e-30; do
  expect_status 0 "" run "$bed" "${tiny[@]}" --set "$extreme" -o "$work/sane.h5md"
  if ! /usr/bin/python3 -c 'import h5py, numpy, sys
f = h5py.File(sys.argv[1], "r")
e = numpy.concatenate([f["observables"][k]["value"][:] for k in ("kinetic_energy", "potential_energy")])
x = f["particles/all/position/value"][-1]
sys.exit(0 if numpy.isfinite(e).all() and (x >= -0.5).all() and (x[:, 2] <= 40).all() else 1)' "$work/sane.h5md"; then
    echo "FAIL: $extreme: energies not finite or spheres outside the box"; failures=$((failures + 1))
  fi
done

# Failed physics: exit 3, a diagnosis, and the result file marked with it.
rm -f "$work/fail.h5md"
expect_status 3 "met the walls more than 64 times in one step" run "$scenarios/gsrd_shaken.toml" -q \
  --set 'system.cells=[8,8,12]' --set run.steps=200 --set shaking.gravity=30 --set shaken.warmup_steps=100 \
  -o "$work/fail.h5md"
if ! "$granflow" info "$work/fail.h5md" 2>/dev/null | grep -q "stop_reason.*the SRD streaming failed"; then
  echo "FAIL: the result of a failed run is not marked with its stop reason"; failures=$((failures + 1))
fi

# Euler-Maruyama past its stability limit (gamma dt >= 2) is allowed, with a
# warning naming the limit: Langevin's velocities then grow at every step
# until the watchdog stops the run; UDSBM's friction falls below the limit
# at t = tau0 (gamma0 dt / 2 - 1), and the run goes on to its end.
sde=(-q --set run.scheme=euler_maruyama --set run.runs=1 --set system.count=50 --set sde.parameters=direct
     --set sde.diffusivity0=1 -o "$work/sde.h5md")
expect_status 3 "the mean squared displacement is" run "$scenarios/langevin_msd.toml" "${sde[@]}" \
  --set sde.gamma0=5 --set run.dt=0.5 --set run.t_stop=2000
expect_status 3 "past its stability limit gamma dt < 2 (gamma0 * dt = 2.5)" run "$scenarios/langevin_msd.toml" \
  "${sde[@]}" --set sde.gamma0=5 --set run.dt=0.5 --set run.t_stop=2000
expect_status 0 "until t = 10, where gamma(t) dt falls below 2" run "$scenarios/udsbm_msd.toml" "${sde[@]}" \
  --set sde.gamma0=4 --set sde.tau0=10 --set run.dt=1 --set run.t_stop=1000

echo "$failures failure(s)"
[[ $failures -eq 0 ]]
