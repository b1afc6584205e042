#!/usr/bin/env bash
# The result files the interop tests open with the field's own tools, one or
# two of every family that writes particle frames or fields, small enough to
# run in seconds, and their exports (extended XYZ, GSD, XDMF and, of 3D
# files, the H5MD for MDAnalysis):
#   haff       event-driven spheres, 3D, periodic, 1000 particles, 34 frames
#   crater     event-driven disks, 2D, walls, two species
#   shaken     soft spheres, 3D, walls on every side
#   vibrated   soft spheres, 3D, periodic in x and y, a vibrating floor
#   gsrd       SRD particles and fields, 3D, periodic
#   srd2d      SRD particles and fields, 2D, sheared (Lees-Edwards)
#   sde        Langevin particles (SDE), 3D, free: the first run's frames
#   haff_final event-driven spheres with one frame (output.positions = final)
#   outputs.sh GRANFLOW SCENARIOS_DIR OUTPUT_DIR
set -eu
granflow="$1"
scenarios="$2"
out="$3"
rm -rf "$out"
mkdir -p "$out"
run() { "$granflow" run "$scenarios/$1.toml" -q -o "$out/$2.h5md" "${@:3}"; }
run haff_cooling haff --set output.positions=all --set run.t_stop=2
run crater_impact crater --set system.count=500 --set run.t_stop=0.02 --set output.positions=all
run shaken_bed shaken --set system.count=50 --set run.t_stop=2 --set output.average_after=1 --set output.positions=all
run vibrated_bed vibrated --set system.count=200 --set run.t_stop=1 --set output.interval=0.25 \
  --set output.average_after=0.25 --set output.positions=all
run gsrd_cooling gsrd --set 'system.cells=[8,8,8]' --set run.steps=40 --set fields.every_steps=20 --set fields.window=5 \
  --set output.points_per_decade=5 --set output.positions=all
run srd_viscosity srd2d --set 'system.cells=[8,8]' --set run.steps=300 --set viscosity.warmup_steps=100 \
  --set fields.every_steps=100 --set output.every_steps=100 --set output.positions=all
run langevin_msd sde --set system.count=200 --set run.t_stop=1 --set run.runs=2 --set output.positions=all
run haff_cooling haff_final --set output.positions=final --set run.t_stop=2
for name in haff crater shaken vibrated gsrd srd2d sde haff_final; do
  for format in xyz gsd xdmf; do "$granflow" export "$out/$name.h5md" --format "$format" 2> /dev/null; done
done
for name in haff shaken vibrated gsrd sde haff_final; do
  "$granflow" export "$out/$name.h5md" --format mdanalysis 2> /dev/null
done
echo "result files and exports in $out"
ls "$out"
