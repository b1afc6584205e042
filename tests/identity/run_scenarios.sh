#!/usr/bin/env bash
# Runs every shipped scenario, small, with particle frames where it has
# them, into OUTPUT_DIR: the result files that compare.py holds against
# those of another build (before and after a change that must not change
# behaviour: every dataset and attribute identical at the same seed).
#   [GRANFLOW_THREADS=N] run_scenarios.sh GRANFLOW SCENARIOS_DIR OUTPUT_DIR   (2 threads unless given)
set -eu
granflow="$1"
scenarios="$2"
out="$3"
mkdir -p "$out"
run() { "$granflow" run "$scenarios/$1.toml" -q --threads "${GRANFLOW_THREADS:-2}" -o "$out/$1.h5md" "${@:2}"; }
run haff_cooling --set run.t_stop=2 --set output.positions=all
run speed_distribution --set system.count=400 --set sampling.snapshots=2
run mixture --set system.count=400 --set sampling.snapshots=2 --set output.positions=final
run crater_impact --set system.count=500 --set run.t_stop=0.02 --set output.positions=all
run scattering
run brownian_edmd --set system.count=300 --set system.radius=0.03 --set run.t_stop=2 --set run.runs=2
run langevin_msd --set system.count=1000 --set run.t_stop=2 --set run.runs=2 --set output.positions=first_last
run udsbm_msd --set system.count=1000 --set run.t_stop=2 --set run.runs=2 --set output.positions=first_last
run shaken_bed --set system.count=50 --set run.t_stop=2 --set output.average_after=1 --set output.positions=all
run vibrated_bed --set system.count=200 --set run.t_stop=1 --set output.interval=0.25 \
  --set output.average_after=0.25 --set output.positions=all
run gsrd_cooling --set 'system.cells=[8,8,8]' --set run.steps=40 --set fields.every_steps=20 --set fields.window=5 \
  --set output.points_per_decade=5 --set output.positions=all
run gsrd_shaken --set 'system.cells=[8,8,16]' --set run.steps=300 --set shaken.warmup_steps=100 \
  --set output.every_steps=50 --set fields.every_steps=100
run srd_poiseuille --set 'system.cells=[20,10]' --set run.steps=1000 --set poiseuille.warmup_steps=200 \
  --set output.every_steps=200 --set output.positions=final
run srd_viscosity --set 'system.cells=[16,16]' --set run.steps=1000 --set viscosity.warmup_steps=200 \
  --set output.every_steps=200
ls "$out"
