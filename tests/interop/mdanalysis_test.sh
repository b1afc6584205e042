#!/usr/bin/env bash
# Result files open in MDAnalysis (Debian's python3-mdanalysis): a 3D
# haff_cooling frame series loads as a trajectory with the same positions and
# box as the file, g(r) is zero inside contact and at contact agrees with the
# Carnahan-Starling value, periodic images unwrap the frames, and the H5MD
# types and units are as granflow documents them. Skips (exit 77) where
# MDAnalysis is not installed.
set -u
granflow="$1"
scenario="$2"
source "$(dirname "$0")/../cli/common.sh"
if ! /usr/bin/python3 -c "import MDAnalysis" 2> /dev/null; then
  echo "skipped: MDAnalysis is not installed (apt-get install python3-mdanalysis)"
  exit 77
fi
"$granflow" run "$scenario" --set output.positions=all --set run.t_stop=2 -q -o "$work/haff.h5md" || exit 1
/usr/bin/python3 -W ignore - "$work/haff.h5md" <<'PY'
import sys, warnings
import h5py, numpy as np
import MDAnalysis as mda
from MDAnalysis.analysis.rdf import InterRDF
path = sys.argv[1]
failures = []
def check(ok, what):
    print(("ok: " if ok else "FAIL: ") + what)
    if not ok: failures.append(what)

f = h5py.File(path, "r")
particles = f["/particles/all"]
n = particles["position/value"].shape[1]
frames = particles["position/value"].shape[0]
edges = particles["box/edges/value"][()]
radius = particles["radius"][()]
# Reduced units have no H5MD unit string MDAnalysis knows, so they are not converted.
u = mda.Universe.empty(n, trajectory=False)
u.load_new(path, format="H5MD", convert_units=False)
check(u.trajectory.n_frames == frames, f"MDAnalysis sees {u.trajectory.n_frames} frames of {frames}")
worst = 0.0
for ts in u.trajectory:
    worst = max(worst, np.abs(u.atoms.positions - particles["position/value"][ts.frame]).max())
    if not np.allclose(ts.dimensions, [*np.diag(edges[ts.frame]), 90, 90, 90]):
        check(False, f"frame {ts.frame}: box {ts.dimensions} is not the file's {np.diag(edges[ts.frame])}")
        break
# MDAnalysis keeps positions in single precision.
check(worst < 1e-6, f"positions equal the file's to {worst:.2g}")
check(abs(u.trajectory[frames - 1].time - particles["position/time"][frames - 1]) < 1e-6, "frame times")

# g(r): zero inside contact (2r), and at contact the Carnahan-Starling value
# chi = (1 - eta/2) / (1 - eta)^3 (Carnahan & Starling 1969) of a hard-sphere fluid.
sigma = 2 * radius[0]
eta = n * np.pi * sigma**3 / 6 / np.prod(np.diag(edges[0]))
rdf = InterRDF(u.atoms, u.atoms, nbins=60, range=(0.2 * sigma, 3 * sigma), exclusion_block=(1, 1)).run()
bins, g = rdf.results.bins, rdf.results.rdf
width = bins[1] - bins[0]
inside = g[bins + width / 2 < sigma]
check(inside.max() == 0.0, f"g(r) = 0 inside contact ({len(inside)} bins)")
contact = g[(bins > sigma) & (bins < sigma + 2 * width)].mean()
chi = (1 - eta / 2) / (1 - eta) ** 3
# Two bins above contact and 49 frames of 1000 particles: about 5 % noise;
# g falls off the contact value by a few % over two bins.
check(abs(contact / chi - 1) < 0.15, f"g at contact {contact:.3f}, Carnahan-Starling {chi:.3f} (eta = {eta:.4f})")
check(abs(g[bins > 2 * sigma].mean() - 1) < 0.05, f"g(r) beyond two diameters {g[bins > 2 * sigma].mean():.3f} ~ 1")

# Images: position + image * L unwraps; between output times no particle moves half a box.
image = particles["image/value"][()]
check(image.dtype.kind == "i", f"image is integer ({image.dtype})")
unwrapped = particles["position/value"][()] + image * np.diag(edges[0])
jump = np.abs(np.diff(unwrapped, axis=0)).max()
wrapped_jump = np.abs(np.diff(particles["position/value"][()], axis=0)).max()
check(jump < 0.5 and wrapped_jump > 0.5, f"unwrapped frames move at most {jump:.3f} (wrapped: {wrapped_jump:.3f})")
check(particles["id"].dtype.kind == "i" and np.array_equal(particles["id"][()], np.arange(n)), "integer ids 0..N-1")
check(np.array_equal(particles["box/edges/time"][()], particles["position/time"][()]), "box shares the frames' times")
for name in ("kinetic_energy", "temperature", "collisions_per_particle"):
    unit = f[f"/observables/{name}/value"].attrs.get("unit")
    check(unit is not None, f"/observables/{name} has unit {unit}")
check(particles["radius"].attrs.get("unit") == "L" and particles["mass"].attrs.get("unit") == "M", "units of radius and mass")
sys.exit(1 if failures else 0)
PY
