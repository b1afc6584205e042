"""Result files in MDAnalysis, the two ways docs/reading-results.md shows.

3D files: `granflow export --format mdanalysis` writes FILE.mda.h5md, which
links to the frames and holds the series at the frames' steps. MDAnalysis 2.4
cannot build a topology from H5MD opened with convert_units=False (needed:
reduced units have no unit string it knows), so the GSD export is the
topology: mda.Universe(FILE.gsd, FILE.mda.h5md, convert_units=False). Every
frame is compared with the file, and the observables MDAnalysis attaches to
each frame (ts.data) must be those at the frame's time, also for a file with
fewer frames than outputs (haff_final, output.positions = final), where the
result file itself would give frame k the k-th output's values. GSD (2D and
3D): mda.Universe(FILE.gsd) takes the topology (types, masses, radii) and the
frames. Physics: g(r) of the hard-sphere gas is 0 inside contact and at
contact Carnahan-Starling's value. Skips (77) where MDAnalysis is not installed.

  mdanalysis_test.py DIR"""
import warnings

import h5py
import numpy as np

from truth import PARTICLE_FILES, Frames, require, start

warnings.simplefilter("ignore")
mda = require("MDAnalysis", "python3-mdanalysis")
InterRDF = require("MDAnalysis.analysis.rdf", "python3-mdanalysis").InterRDF
directory, check = start("MDAnalysis " + mda.__version__)


def open_h5md(name):
    return mda.Universe(f"{directory}/{name}.gsd", f"{directory}/{name}.mda.h5md", convert_units=False)


for name, dimension in PARTICLE_FILES + [("haff_final", 3)]:
    truth = Frames(f"{directory}/{name}.h5md")
    # The result file carries its reduced units, which MDAnalysis would refuse; the export's datasets carry none.
    with h5py.File(f"{directory}/{name}.h5md", "r") as f:
        p = f["/particles/all"]
        units = [p[d].attrs.get("unit") for d in ("position/value", "velocity/value", "position/time")]
    check(units == ["L", "L T-1", "T"], f"{name}.h5md: units of position, velocity and time {units}")
    if dimension == 3:
        u = open_h5md(name)
        check(u.trajectory.n_frames == truth.frames, f"{name}.mda.h5md: {u.trajectory.n_frames} frames of {truth.frames}")
        worst, mismatched, attached = 0.0, set(), set()
        for ts in u.trajectory:
            k = ts.frame
            worst = max(worst, np.abs(u.atoms.positions - truth.positions[k]).max() / truth.edges.max(),
                        np.abs(ts.velocities - truth.velocities[k]).max() / max(1.0, np.abs(truth.velocities[k]).max()))
            if not np.allclose(ts.dimensions, [*truth.edges[k], 90, 90, 90]) or abs(ts.time - truth.times[k]) > 1e-6:
                check(False, f"{name}.mda.h5md frame {k}: box {ts.dimensions}, time {ts.time}")
                break
            for key, value in ts.data.items():
                if key not in truth.observables:
                    continue
                attached.add(key)
                times, values = truth.observables[key]
                at = np.flatnonzero(times == truth.times[k])
                if len(at) != 1 or not np.array_equal(np.asarray(value), values[at[0]]):
                    mismatched.add(key)
        # MDAnalysis keeps positions in single precision.
        check(worst < 1e-6, f"{name}.mda.h5md: positions and velocities within {worst:.2g} (relative)")
        # Every series sampled at every frame's time reaches ts.data.
        sampled = {key for key, (times, _) in truth.observables.items() if set(truth.times) <= set(times)}
        check(not mismatched and attached == sampled,
              f"{name}.mda.h5md: ts.data holds each observable at the frame's time ({len(attached)} of "
              f"{len(truth.observables)} series are sampled at every frame; wrong: {sorted(mismatched)}, "
              f"missing: {sorted(sampled - attached)})")
        check(np.allclose(u.atoms.masses, truth.mass, rtol=1e-6), f"{name}: masses from the GSD topology")
        print(f"  {name}.mda.h5md: {u.trajectory.n_frames} frames of {len(u.atoms)} atoms, box {u.dimensions[:3]}, "
              f"observables per frame {sorted(u.trajectory[0].data)}")
    g = mda.Universe(f"{directory}/{name}.gsd")
    check(len(g.atoms) == truth.count and g.trajectory.n_frames == truth.frames,
          f"{name}.gsd: {len(g.atoms)} atoms, {g.trajectory.n_frames} frames")
    worst = 0.0
    for ts in g.trajectory:
        centred = truth.padded(truth.positions[ts.frame] - 0.5 * truth.edges[ts.frame])
        worst = max(worst, np.abs(g.atoms.positions - centred).max() / truth.edges.max())
    expected = [*truth.edges[-1], 0.0] if dimension == 2 else list(truth.edges[-1])
    check(np.allclose(g.dimensions[:3], expected, rtol=1e-6), f"{name}.gsd: box {g.dimensions[:3]}")
    check(worst < 1e-6, f"{name}.gsd: positions within {worst:.2g} (relative)")
    # Point particles (SRD) have no diameter: HOOMD's default, 1.
    radii = truth.radius if truth.radius is not None else np.full(truth.count, 0.5)
    check(np.allclose(g.atoms.masses, truth.mass, rtol=1e-6) and np.allclose(g.atoms.radii, radii, rtol=1e-6)
          and list(g.atoms.types) == [str(s) for s in truth.species], f"{name}.gsd: masses, radii and types")

# g(r) of the hard-sphere gas: zero inside contact (2r), and at contact the
# Carnahan-Starling value chi = (1 - eta/2) / (1 - eta)^3 (Carnahan & Starling 1969).
truth = Frames(f"{directory}/haff.h5md")
u = open_h5md("haff")
sigma = 2 * truth.radius[0]
eta = truth.count * np.pi * sigma**3 / 6 / np.prod(truth.edges[0])
rdf = InterRDF(u.atoms, u.atoms, nbins=60, range=(0.2 * sigma, 3 * sigma), exclusion_block=(1, 1)).run()
bins, g = rdf.results.bins, rdf.results.rdf
width = bins[1] - bins[0]
inside = g[bins + width / 2 < sigma]
check(inside.max() == 0.0, f"g(r) = 0 inside contact ({len(inside)} bins)")
contact = g[(bins > sigma) & (bins < sigma + 2 * width)].mean()
chi = (1 - eta / 2) / (1 - eta) ** 3
# Two bins above contact, tens of frames of 1000 particles: about 5 % noise;
# g falls off the contact value by a few % over two bins.
check(abs(contact / chi - 1) < 0.15, f"g at contact {contact:.3f}, Carnahan-Starling {chi:.3f} (eta = {eta:.4f})")
check(abs(g[bins > 2 * sigma].mean() - 1) < 0.05, f"g(r) beyond two diameters {g[bins > 2 * sigma].mean():.3f} ~ 1")
check.close()
