#!/usr/bin/python3
"""Draws the figures a physicist expects from a granflow result file.

Usage: /usr/bin/python3 tools/plot.py OUT.h5 [-o FIGURE.png]

haff_cooling: T(t)/T0 on log-log axes with Haff's law T0/(1 + t/tau0)^2
(seed 000 eqs. 2.40 and 2.45), tau0 from the Enskog collision frequency of the
initial state, and the ratio to Haff's law below it.
"""
import argparse
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def scenario_of(f):
    value = f["/parameters"].attrs["scenario"]
    return value.decode() if isinstance(value, bytes) else str(value)


def plot_haff(f, output):
    time = f["/observables/temperature/time"][()]
    temperature = f["/observables/temperature/value"][()]
    derived = f["/parameters/derived"].attrs
    tau0 = float(derived["haff_tau0"])
    t0 = float(derived["initial_temperature"])
    xi = float(f["/parameters/collision"].attrs["restitution"])
    eta = float(derived["packing_fraction"])
    n = int(f["/parameters/system"].attrs["count"])
    dim = int(f["/parameters/system"].attrs["dimension"])

    keep = time > 0
    t, ratio = time[keep], temperature[keep] / t0
    theory = 1.0 / (1.0 + t / tau0) ** 2

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.4, 6.4), sharex=True,
                                      gridspec_kw={"height_ratios": [3, 1]})
    top.loglog(t, ratio, "o", ms=3, label="granflow EDMD")
    top.loglog(t, theory, "-", label=r"Haff: $(1 + t/\tau_0)^{-2}$")
    top.loglog(t, (tau0 / t) ** 2, ":", color="grey", label=r"$(t/\tau_0)^{-2}$")
    top.set_ylim(min(ratio.min(), theory.min()) / 2, 2)
    top.set_ylabel(r"$T(t)/T_0$")
    top.set_title(f"Haff cooling, {dim}D, N = {n}, $\\eta$ = {eta:.3f}, $\\xi$ = {xi:g}, "
                  f"$\\tau_0$ = {tau0:.3g}", fontsize=10)
    top.legend()
    bottom.semilogx(t, ratio / theory, "o", ms=3)
    bottom.axhline(1.0, color="k", lw=0.8)
    bottom.set_ylabel("T / Haff")
    bottom.set_xlabel("t")
    fig.tight_layout()
    fig.savefig(output, dpi=120)
    print(f"wrote {output}")


PLOTTERS = {"haff_cooling": plot_haff}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("file", help="granflow H5MD result file")
    parser.add_argument("-o", "--output", help="figure file (default: FILE with .png)")
    args = parser.parse_args()
    output = args.output or (args.file[:-3] if args.file.endswith(".h5") else args.file) + ".png"
    with h5py.File(args.file, "r") as f:
        scenario = scenario_of(f)
        if scenario not in PLOTTERS:
            sys.exit(f"plot.py: no figure defined for scenario '{scenario}'")
        PLOTTERS[scenario](f, output)


if __name__ == "__main__":
    main()
