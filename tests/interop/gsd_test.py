"""granflow export --format gsd, read by the gsd package itself
(gsd.hoomd.open, as HOOMD-blue, OVITO and freud read GSD): for every file of
particle frames, the frame count, N, the box and dimensions (2D as HOOMD
writes it: Lz = 0), step and time, positions (shifted to HOOMD's centred box),
velocities, images, masses, diameters and types against the result file.
Skips (77) where gsd is not installed.

  gsd_test.py DIR"""

import numpy as np

from truth import PARTICLE_FILES, Frames, require, start

gsd = require("gsd", "python3-gsd")
require("gsd.hoomd", "python3-gsd")
directory, check = start("gsd " + gsd.__version__)
for name, dimension in PARTICLE_FILES:
    truth = Frames(f"{directory}/{name}.h5md")
    with gsd.hoomd.open(f"{directory}/{name}.gsd", "rb") as trajectory:
        check(len(trajectory) == truth.frames, f"{name}.gsd: {len(trajectory)} frames of {truth.frames}")
        worst_position = worst_velocity = 0.0
        for k, frame in enumerate(trajectory):
            box = frame.configuration.box
            edges = truth.edges[k]
            expected_box = [edges[0], edges[1], edges[2] if dimension == 3 else 0.0, 0, 0, 0]
            if frame.configuration.dimensions != dimension or not np.allclose(box, expected_box, rtol=1e-6):
                check(False, f"{name}.gsd frame {k}: box {box}, dimensions {frame.configuration.dimensions}")
                break
            if frame.particles.N != truth.count or frame.configuration.step != truth.steps[k] \
                    or abs(frame.log["time"][0] - truth.times[k]) > 1e-12:
                check(False, f"{name}.gsd frame {k}: N {frame.particles.N}, step {frame.configuration.step}, "
                             f"time {frame.log['time']}")
                break
            centred = truth.padded(truth.positions[k] - 0.5 * edges[:dimension])
            worst_position = max(worst_position, np.abs(frame.particles.position - centred).max())
            worst_velocity = max(worst_velocity, np.abs(frame.particles.velocity - truth.padded(truth.velocities[k])).max()
                                 / max(1.0, np.abs(truth.velocities[k]).max()))
            if truth.images is not None and not np.array_equal(frame.particles.image, truth.padded(truth.images[k])):
                check(False, f"{name}.gsd frame {k}: images differ")
            inside = np.all(np.abs(frame.particles.position[:, :dimension]) <= 0.5 * edges[:dimension] * (1 + 1e-6)
                            + (2 * truth.radius.max() if truth.radius is not None else 0.0))
            if not inside:
                check(False, f"{name}.gsd frame {k}: particles outside HOOMD's box")
        # Single precision, as HOOMD stores positions.
        check(worst_position < 1e-6 * truth.edges.max(), f"{name}.gsd: positions within {worst_position:.2g}")
        check(worst_velocity < 1e-6, f"{name}.gsd: velocities within {worst_velocity:.2g} (relative)")
        first = trajectory[0]
        check(np.allclose(first.particles.mass, truth.mass, rtol=1e-6), f"{name}.gsd: masses")
        if truth.radius is not None:
            check(np.allclose(first.particles.diameter, 2 * truth.radius, rtol=1e-6), f"{name}.gsd: diameters")
        types = [first.particles.types[t] for t in first.particles.typeid]
        check(types == [str(s) for s in truth.species],
              f"{name}.gsd: types {sorted(set(types))} from species {sorted(set(truth.species.tolist()))}")
        print(f"  {name}.gsd: {len(trajectory)} frames of {first.particles.N} particles, box "
              f"{list(first.configuration.box[:3])}, {first.configuration.dimensions}D, types {first.particles.types}")
check.close()
