#!/usr/bin/python3
"""The measured numbers the documentation quotes, measured again.

Each check runs the command a page names (at the size it names), reads the
number from what the run prints or writes, and finds the page's number by
a pattern. The two must agree to the digits the page gives. A change that
moves a result then fails here until the page says what the program does.

    docs_numbers_test.py GRANFLOW SOURCE_DIR
Skips (exit 77) where /usr/bin/python3 lacks h5py or numpy.
"""

import os
import re
import subprocess
import sys
import tempfile


def run(granflow, source, directory, arguments):
    done = subprocess.run([granflow, "run", *arguments], cwd=directory, capture_output=True, text=True, timeout=600)
    if done.returncode != 0:
        raise RuntimeError(f"granflow run {' '.join(arguments)} exited with {done.returncode}: {done.stderr[-1000:]}")
    return done.stderr + done.stdout


def printed(pattern):
    """The first number the run's log prints after `pattern` (a regular expression)."""
    def read(log, directory):
        found = re.search(pattern + r"\s*(-?[0-9]+(?:\.[0-9]+)?)", log)
        if not found:
            raise RuntimeError(f"the run printed nothing matching {pattern!r}")
        return float(found.group(1))
    return read


def viscoelastic_slope(log, directory):
    import h5py
    import numpy as np
    with h5py.File(os.path.join(directory, "viscoelastic.h5md"), "r") as f:
        t = f["/observables/temperature/time"][()]
        temperature = f["/observables/temperature/value"][()]
        tau = float(f["/parameters/derived"].attrs["haff_tau0"])
    late = t >= 100 * tau
    return float(np.polyfit(np.log(t[late]), np.log(temperature[late]), 1)[0])


def documented(source, page, pattern):
    """The number the page gives where `pattern` (a regular expression with one group) matches."""
    with open(os.path.join(source, page)) as f:
        text = " ".join(f.read().split()).replace("−", "-")
    found = re.search(pattern, text)
    if not found:
        raise RuntimeError(f"{page} has nothing matching {pattern!r}")
    return found.group(1)


SPEEDS_2D = ["scenarios/speed_distribution.toml", "-o", "speeds2d.h5md"]
SPEEDS_3D = ["scenarios/speed_distribution.toml", "--set", "system.dimension=3", "--set", "system.radius=0.01",
             "-o", "speeds3d.h5md"]
EDMD = ["scenarios/brownian_edmd.toml", "-o", "edmd.h5md"]
VISCOELASTIC = ["scenarios/haff_cooling.toml", "--set", "collision.restitution=1", "--set",
                "collision.viscoelastic_speed=1e7", "--set", "system.count=4000", "--set", "run.t_stop=1e6",
                "--set", "output.spacing=log", "-o", "viscoelastic.h5md"]

# (what, command, how the run gives the number, page, pattern of the page's number)
CHECKS = [
    ("2D mean speed", SPEEDS_2D, printed(r"speeds: mean"), "docs/scenarios.md", r"2D: mean ([0-9]+(?:\.[0-9]+)?)"),
    ("2D chi-square", SPEEDS_2D, printed(r"chi-square"), "docs/scenarios.md", r"2D: mean .*?chi-square ([0-9]+(?:\.[0-9]+)?)"),
    ("3D mean speed", SPEEDS_3D, printed(r"speeds: mean"), "docs/scenarios.md", r"3D: mean ([0-9]+(?:\.[0-9]+)?)"),
    ("3D chi-square", SPEEDS_3D, printed(r"chi-square"), "docs/scenarios.md", r"3D: mean .*?chi-square ([0-9]+(?:\.[0-9]+)?)"),
    ("2D mean speed (figures)", SPEEDS_2D, printed(r"speeds: mean"), "docs/figures.md", r"2D mean ([0-9]+(?:\.[0-9]+)?)"),
    ("3D mean speed (figures)", SPEEDS_3D, printed(r"speeds: mean"), "docs/figures.md", r"3D ([0-9]+\.[0-9]+) \("),
    ("molecular MSD slope / 6 D0", EDMD, printed(r"slope over the last decade [0-9.]+ ="), "docs/diffusion.md",
     r"0\.[0-9]+ = ([0-9]+\.[0-9]+) × 6 D0"),
    ("viscoelastic cooling exponent", VISCOELASTIC, viscoelastic_slope, "docs/event-driven.md",
     r"T ∝ t\^(-[0-9]+\.[0-9]+), against"),
]


def agrees(measured, quoted):
    decimals = len(quoted.split(".")[1]) if "." in quoted else 0
    return round(measured, decimals) == round(float(quoted), decimals)


def main():
    granflow, source = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    try:
        import h5py  # noqa: F401
        import numpy  # noqa: F401
    except ImportError:
        print("skipped: /usr/bin/python3 has no h5py or numpy (apt-get install python3-h5py)")
        return 77
    failures = 0
    logs = {}
    with tempfile.TemporaryDirectory(prefix="granflow_docs_numbers_") as directory:
        for what, command, measure, page, pattern in CHECKS:
            try:
                key = tuple(command)
                if key not in logs:
                    logs[key] = run(granflow, source, directory, [os.path.join(source, command[0]), *command[1:]])
                measured = measure(logs[key], directory)
                quoted = documented(source, page, pattern)
            except RuntimeError as error:
                failures += 1
                print(f"FAIL: {what}: {error}")
                continue
            if agrees(measured, quoted):
                print(f"ok: {what}: {page} says {quoted}, measured {measured:.6g}")
            else:
                failures += 1
                print(f"FAIL: {what}: {page} says {quoted}, the program gives {measured:.6g}")
    print(f"{len(CHECKS)} numbers, {failures} disagree")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
