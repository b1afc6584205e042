"""What a result file holds, read with h5py: the ground truth that the
interop tests compare each tool's view against, and the list of files the
fixture (outputs.sh) writes."""
import importlib
import os
import sys

import h5py
import numpy as np

def require(module, package):
    """The module, or exit 77 (the test is skipped) saying which Debian package has it."""
    try:
        return importlib.import_module(module)
    except ImportError:
        print(f"skipped: {module} is not installed (apt-get install {package})")
        sys.exit(77)


# (name, dimension) of the files with particle frames; the SRD files hold fields.
PARTICLE_FILES = [("haff", 3), ("crater", 2), ("shaken", 3), ("vibrated", 3), ("gsrd", 3), ("srd2d", 2), ("sde", 3)]
FIELD_FILES = [("gsrd", 3), ("srd2d", 2)]


class Frames:
    def __init__(self, path):
        with h5py.File(path, "r") as f:
            p = f["/particles/all"]
            self.positions = p["position/value"][()]
            self.times = p["position/time"][()]
            self.steps = p["position/step"][()]
            self.velocities = p["velocity/value"][()]
            self.images = p["image/value"][()] if "image" in p else None
            self.frames, self.count, self.dimension = self.positions.shape
            if isinstance(p["box/edges"], h5py.Group):
                self.edges = np.array([np.diag(m) for m in p["box/edges/value"][()]])
            else:
                self.edges = np.tile(p["box/edges"][()], (self.frames, 1))
            self.periodic = [b.decode() == "periodic" for b in p["box"].attrs["boundary"]]
            self.radius = p["radius"][()] if "radius" in p else None  # SRD and SDE particles are points
            self.mass = p["mass"][()]
            self.species = p["species"][()] if "species" in p else np.zeros(self.count, dtype=int)
            self.observables = {name: (g["time"][()], g["value"][()]) for name, g in f["/observables"].items()}

    def padded(self, values):
        """[N, d] as [N, 3], the plane z = 0 in 2D."""
        out = np.zeros((values.shape[0], 3), dtype=values.dtype)
        out[:, : values.shape[1]] = values
        return out


def start(tool):
    """The output directory (the first argument) and the checks of one tool."""
    return sys.argv[1], Checks(tool)


class Checks:
    def __init__(self, tool):
        self.tool, self.failures = tool, []

    def __call__(self, ok, what):
        print(("ok: " if ok else "FAIL: ") + f"{self.tool}: {what}")
        if not ok:
            self.failures.append(what)

    def close(self, skip_teardown=False):
        print(f"{self.tool}: {'all checks passed' if not self.failures else f'{len(self.failures)} failed'}")
        code = 1 if self.failures else 0
        if skip_teardown:
            # pvpython under Xvfb can fail in its OpenGL teardown after the work is done.
            sys.stdout.flush()
            os._exit(code)
        sys.exit(code)
