#!/usr/bin/env python3
"""The vibrated bed side by side with LAMMPS: the centre-of-mass height and
the number density against height, averaged over the frames from --from on,
with standard errors from blocks of whole shaking periods (the frames of one
period are correlated; period means much less so).

  granflow run scenarios/vibrated_bed.toml --set run.dt=0.001 --set run.t_stop=20 \\
      --set output.interval=0.05 --set output.positions=all -o bed.h5md
  mpirun -np 2 lmp -in tools/lammps/vibrated_bed_frames.in -var anchor ANCHOR -var frames lammps_z.dump -log none
  /usr/bin/python3 tools/compare_vibrated_bed.py bed.h5md lammps_z.dump

Prints both codes' figures, their difference in combined standard errors,
and exits 1 where a difference exceeds --sigma (default 3) of them.
"""
import argparse
import sys

import h5py
import numpy as np


def granflow_frames(path):
    with h5py.File(path, "r") as f:
        position = f["particles/all/position"]
        return position["time"][()], position["value"][:, :, 2]


def lammps_frames(path, dt):
    times, heights = [], []
    with open(path) as f:
        while True:
            line = f.readline()
            if not line:
                break
            if line.startswith("ITEM: TIMESTEP"):
                times.append(int(f.readline()) * dt)
            elif line.startswith("ITEM: NUMBER OF ATOMS"):
                count = int(f.readline())
            elif line.startswith("ITEM: ATOMS"):
                rows = np.loadtxt([f.readline() for _ in range(count)])
                heights.append(rows[np.argsort(rows[:, 0]), 1])
    return np.array(times), np.array(heights)


def block_statistics(samples, per_block):
    """Mean and standard error of the mean of `samples` (frames first) over
    consecutive blocks of `per_block` frames."""
    blocks = len(samples) // per_block
    means = np.array([samples[b * per_block:(b + 1) * per_block].mean(axis=0) for b in range(blocks)])
    return means.mean(axis=0), means.std(axis=0, ddof=1) / np.sqrt(blocks), blocks


def summarise(name, times, heights, start, period, layer, top):
    keep = times >= start - 1e-9
    times, heights = times[keep], heights[keep]
    per_period = int(round(period / (times[1] - times[0])))
    edges = np.arange(0.0, top + layer, layer)
    density = np.array([np.histogram(z, edges)[0] for z in heights])
    com = block_statistics(heights.mean(axis=1), per_period)
    profile = block_statistics(density, per_period)
    print(f"{name}: {len(times)} frames from t = {times[0]:g} to {times[-1]:g}, {com[2]} periods")
    return com, profile, edges


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("granflow")
    parser.add_argument("lammps")
    parser.add_argument("--from", dest="start", type=float, default=10.0, help="first time averaged")
    parser.add_argument("--period", type=float, default=1.0, help="shaking period (one block)")
    parser.add_argument("--dt", type=float, default=0.001, help="LAMMPS's time step")
    parser.add_argument("--layer", type=float, default=1.0, help="layer thickness of the profile")
    parser.add_argument("--top", type=float, default=30.0, help="height of the profile")
    parser.add_argument("--sigma", type=float, default=3.0)
    a = parser.parse_args()
    ours = summarise("granflow", *granflow_frames(a.granflow), a.start, a.period, a.layer, a.top)
    theirs = summarise("LAMMPS", *lammps_frames(a.lammps, a.dt), a.start, a.period, a.layer, a.top)
    worst = 0.0
    (m1, e1, _), (m2, e2, _) = ours[0], theirs[0]
    z = (m1 - m2) / np.hypot(e1, e2)
    worst = max(worst, abs(z))
    print(f"centre of mass height: granflow {m1:.4f} +- {e1:.4f}, LAMMPS {m2:.4f} +- {e2:.4f} ({z:+.2f} sigma)")
    print(" layer        granflow            LAMMPS     difference")
    (p1, s1, _), (p2, s2, _), edges = ours[1], theirs[1], ours[2]
    for k in range(len(p1)):
        if p1[k] < 1 and p2[k] < 1:
            continue
        z = (p1[k] - p2[k]) / max(np.hypot(s1[k], s2[k]), 1e-12)
        worst = max(worst, abs(z))
        print(f"{edges[k]:4.0f}-{edges[k + 1]:<4.0f} {p1[k]:8.1f} +- {s1[k]:5.1f}  {p2[k]:8.1f} +- {s2[k]:5.1f}  {z:+6.2f} sigma")
    print(f"largest difference: {worst:.2f} combined standard errors (limit {a.sigma})")
    sys.exit(0 if worst <= a.sigma else 1)


if __name__ == "__main__":
    main()
