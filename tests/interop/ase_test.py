"""granflow export --format xyz, read by ASE (ase.io.read, extended XYZ in
the conventions OVITO also reads): for every file of particle frames, the
frame count, particle count, cell and pbc, Time and Step, positions,
velocities (ASE's get_velocities, from momenta and masses), masses,
radii, species (as chemical symbols and typeid) and images against the result
file. Skips (77) where ASE is not installed.

  ase_test.py DIR"""

import numpy as np

from truth import PARTICLE_FILES, Frames, require, start

ase = require("ase", "python3-ase")
require("ase.io", "python3-ase")
directory, check = start("ASE " + ase.__version__)
for name, dimension in PARTICLE_FILES:
    truth = Frames(f"{directory}/{name}.h5md")
    frames = ase.io.read(f"{directory}/{name}.xyz", index=":")
    check(len(frames) == truth.frames, f"{name}.xyz: {len(frames)} frames of {truth.frames}")
    worst = 0.0
    for k, atoms in enumerate(frames):
        cell = np.diag(atoms.cell.array)
        expected = np.array([*truth.edges[k], 1.0] if dimension == 2 else truth.edges[k])
        if len(atoms) != truth.count or not np.allclose(cell, expected) or \
                atoms.info["Time"] != truth.times[k] or atoms.info["Step"] != truth.steps[k]:
            check(False, f"{name}.xyz frame {k}: {len(atoms)} atoms, cell {cell}, info {atoms.info}")
            break
        scale = max(1.0, np.abs(truth.velocities[k]).max())
        worst = max(worst, np.abs(atoms.positions - truth.padded(truth.positions[k])).max(),
                    np.abs(atoms.get_velocities() - truth.padded(truth.velocities[k])).max() / scale)
        if truth.images is not None and not np.array_equal(atoms.arrays["image"], truth.padded(truth.images[k])):
            check(False, f"{name}.xyz frame {k}: images differ")
    first = frames[0]
    check(worst < 1e-9 * max(1.0, truth.edges.max()), f"{name}.xyz: positions and velocities within {worst:.2g}")
    check(list(first.pbc) == truth.periodic + [False] * (3 - dimension), f"{name}.xyz: pbc {list(first.pbc)}")
    check(np.allclose(first.get_masses(), truth.mass, rtol=1e-9), f"{name}.xyz: get_masses() gives the run's masses")
    if truth.radius is not None:
        check(np.allclose(first.arrays["radius"], truth.radius, rtol=1e-9), f"{name}.xyz: radii")
    else:
        check("radius" not in first.arrays, f"{name}.xyz: point particles, no radius column")
    check(np.array_equal(first.arrays["typeid"], truth.species)
          and np.array_equal(first.get_atomic_numbers(), truth.species + 1),
          f"{name}.xyz: species as typeid and as atomic number species + 1 ({sorted(set(first.get_chemical_symbols()))})")
    print(f"  {name}.xyz: {len(frames)} frames of {len(first)} atoms, cell {np.diag(first.cell.array)}, "
          f"pbc {list(first.pbc)}, arrays {sorted(first.arrays)}")
check.close()
