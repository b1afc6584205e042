#!/usr/bin/python3
"""A stored state whose density falls off along z: a copy of a granflow result
file (its last frame of particles) with every z moved to L (z / L)^2, so that
the lower half of the box holds 1/sqrt(2) = 71 % of the particles. With
--temperature, the velocities are scaled to that kT (a stored state's
velocities replace srd.temperature). For runs from `initial.from` that load
the ranks of an MPI run unevenly (load balance: docs/srd.md).

  denser_at_one_end.py IN OUT [--temperature KT]"""
import argparse
import shutil

import h5py

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("input")
parser.add_argument("output")
parser.add_argument("--temperature", type=float, default=None)
arguments = parser.parse_args()
shutil.copy(arguments.input, arguments.output)
with h5py.File(arguments.output, "r+") as f:
    edges = f["particles/all/box/edges/value"][-1]  # a vector, or H5MD's matrix of edge vectors
    length = float(edges[2] if edges.ndim == 1 else edges[2][2])
    positions = f["particles/all/position/value"]
    frame = positions[-1]
    frame[:, 2] = length * (frame[:, 2] / length) ** 2
    positions[-1] = frame
    if arguments.temperature is not None:
        velocities = f["particles/all/velocity/value"]
        v = velocities[-1]
        velocities[-1] = v * (arguments.temperature / (v**2).mean()) ** 0.5
