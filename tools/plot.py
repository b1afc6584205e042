#!/usr/bin/python3
"""Draws the figures a physicist expects from granflow result files.

Usage: /usr/bin/python3 tools/plot.py OUT.h5 [MORE.h5 ...] [-o FIGURE.png]
       /usr/bin/python3 tools/plot.py SWEEP/summary.h5 [--x KEY] [--y NAME] [--logx]

haff_cooling: T(t)/T0 on log-log axes with Haff's law T0/(1 + t/tau0)^2
  (Haff 1983) and the ratio to Haff's law below it; several files overlaid.
speed_distribution: initial (delta) and equilibrium speed histograms with the
  Maxwell-Boltzmann density at the measured temperature.
mixture: mean kinetic energy of all particles and of each species against
  time (several files, e.g. one per xi, are overlaid), and the speed
  histograms of each species with Maxwell-Boltzmann.
scattering: scattering angle against b/R12 with the analytic curve.
crater_impact: the bed before and after the impact drawn to scale (disks
  of their true radii; crater disks coloured), and crater size, projectile
  depth and kinetic energy against time.
langevin_msd, udsbm_msd: ensemble MSD (standard error over runs) with the
  theory (the exact moment equations), the time-averaged
  MSD against lag, the diffusivity and the ergodicity-breaking parameter.
brownian_edmd: MSD of the event-driven gas with the Langevin / UDSBM theory
  (Enskog D0), time-averaged MSD, and the diffusivity against time.
gsrd_cooling: temperature and convective energy with Haff's law, the density
  fluctuation, the Sonine coefficient a2, the Mach number (several files
  overlaid, e.g. one per restitution), the velocity distribution and a
  density slice of the first file.
Several files of one scenario are told apart in the legend by the
  configuration keys whose values differ between them. An ensemble's file
  (run.runs > 1) is drawn as its mean with a band of two standard errors.
sweep summaries: each summary observable (mean and standard error over
  repeats) against a swept key.
--srd-viscosity-theory (no files): the kinetic (streaming) viscosity of SRD
  against the temperature for several rotation angles beside the
  temperature-independent collisional one (Kikuchi et al. 2003), at
  --n0 and --dt: where the curves cross, collisions carry the momentum.
"""
import argparse
import glob
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def unit_of(f, path):
    """The H5MD unit of a dataset, for axis labels ("" where it has none)."""
    unit = f[path].attrs.get("unit", "") if path in f else ""
    unit = text(unit) if unit else ""
    return "" if unit in ("", "1") else f" [{unit}]"


def scenario_of(f):
    value = f["/parameters"].attrs["scenario"]
    return value.decode() if isinstance(value, bytes) else str(value)


def save(fig, output):
    fig.tight_layout()
    fig.savefig(output, dpi=120)
    print(f"wrote {output}")


def configuration_of(f):
    """Every configuration key of a result file ("section.key" -> value), the
    derived quantities left out."""
    keys = {}
    for section, group in f["/parameters"].items():
        if section == "derived" or not isinstance(group, h5py.Group):
            continue
        for name, value in group.attrs.items():
            value = text(value) if isinstance(value, (bytes, str)) else np.asarray(value).tolist()
            keys[f"{section}.{name}"] = value
    return keys


def overlay_labels(files):
    """A legend label per file: the keys whose values differ between the
    files (the file name where none does)."""
    configurations = [configuration_of(f) for f in files]
    names = sorted(set().union(*configurations))
    differing = [k for k in names if len({repr(c.get(k)) for c in configurations}) > 1]
    if not differing:
        return [os.path.basename(f.filename) for f in files]
    return [", ".join(f"{k} = {c.get(k)}" for k in differing) for c in configurations]


def label_speed_axes(*axes):
    for ax in axes:
        ax.set_xlabel("speed v [L T-1]")
        ax.set_ylabel("probability density [T L-1]")


def plot_haff(files, output):
    first = files[0]
    snapshot = (int(first["/parameters/system"].attrs["dimension"]) == 2 and "particles" in first
                and "position" in first["particles/all"])
    fig = plt.figure(figsize=(12.4 if snapshot else 6.4, 8.0))
    grid = fig.add_gridspec(3, 2 if snapshot else 1, height_ratios=[3, 1, 1.2])
    top = fig.add_subplot(grid[0, 0])
    bottom = fig.add_subplot(grid[1, 0], sharex=top)
    collisions = fig.add_subplot(grid[2, 0], sharex=top)
    if snapshot:
        draw_disks(fig.add_subplot(grid[:, 1]), first)
    labels = overlay_labels(files) if len(files) > 1 else ["granflow EDMD"]
    lowest = 1.0
    for k, (f, label) in enumerate(zip(files, labels)):
        time = f["/observables/temperature/time"][()]
        temperature = f["/observables/temperature/value"][()]
        derived = f["/parameters/derived"].attrs
        tau0 = float(derived["haff_tau0"])
        exponent = float(derived.get("haff_exponent", 2.0))  # 5/3: viscoelastic spheres
        t0 = float(derived["initial_temperature"])
        keep = time > 0
        t, ratio = time[keep], temperature[keep] / t0
        theory = 1.0 / (1.0 + t / tau0) ** exponent
        colour = f"C{k}"
        if runs_of(f) > 1:
            label = f"{label}, mean of {runs_of(f)} runs"
            error = standard_error(f, "temperature")[keep] / t0
            top.fill_between(t, ratio - 2 * error, ratio + 2 * error, color=colour, alpha=0.3, lw=0)
            bottom.fill_between(t, (ratio - 2 * error) / theory, (ratio + 2 * error) / theory, color=colour,
                                alpha=0.3, lw=0)
        top.loglog(t, ratio, "o", ms=3, color=colour, label=label)
        top.loglog(t, theory, "-", color=colour, lw=0.8,
                   label=(r"Haff: $(1 + t/\tau_0)^{-2}$" if exponent == 2.0 else
                          r"viscoelastic: $(1 + t/\tau_0)^{-5/3}$") if k == 0 else None)
        bottom.semilogx(t, ratio / theory, "o", ms=3, color=colour)
        if "collisions_per_particle" in f["/observables"]:
            t_c, count = series(f, "collisions_per_particle")
            collisions.semilogx(t_c[t_c > 0], count[t_c > 0], "-", color=colour)
        lowest = min(lowest, ratio.min(), theory.min())
    f = files[0]
    tau0 = float(f["/parameters/derived"].attrs["haff_tau0"])
    t = f["/observables/temperature/time"][()]
    t = t[t > 0]
    exponent = float(f["/parameters/derived"].attrs.get("haff_exponent", 2.0))
    top.loglog(t, (tau0 / t) ** exponent, ":", color="grey",
               label=rf"$(t/\tau_0)^{{-{exponent:.3g}}}$" + (" (first file)" if len(files) > 1 else ""))
    top.set_ylim(lowest / 2, 2)
    top.set_ylabel(r"$T(t)/T_0$")
    n = int(f["/parameters/system"].attrs["count"])
    dim = int(f["/parameters/system"].attrs["dimension"])
    if len(files) == 1:
        xi = float(f["/parameters/collision"].attrs["restitution"])
        g_ve = float(f["/parameters/collision"].attrs.get("viscoelastic_speed", 0.0))
        eta = float(f["/parameters/derived"].attrs["packing_fraction"])
        law = f"viscoelastic, $g_{{ve}}$ = {g_ve:g}" if g_ve > 0 else f"$\\xi$ = {xi:g}"
        top.set_title(f"Haff cooling, {dim}D, N = {n}, $\\eta$ = {eta:.3f}, {law}, "
                      f"$\\tau_0$ = {tau0:.3g}", fontsize=10)
    else:
        top.set_title(f"Haff cooling, {dim}D, {len(files)} runs", fontsize=10)
    top.legend(fontsize=8)
    bottom.axhline(1.0, color="k", lw=0.8)
    bottom.set_ylabel("T / Haff")
    collisions.set_ylabel("collisions per particle")
    collisions.set_xlabel("t [T]")
    save(fig, output)


def draw_disks(ax, f):
    """The last stored frame of a 2D gas, each disk to scale (clusters show)."""
    group = f["particles/all"]
    position = group["position/value"][-1]
    t = group["position/time"][-1]
    radius = float(f["/parameters/system"].attrs["radius"])
    edges = f["particles/all/box/edges/value"][-1] if isinstance(f["particles/all/box/edges"], h5py.Group) \
        else f["particles/all/box/edges"][()]
    from matplotlib.collections import EllipseCollection
    ax.add_collection(EllipseCollection(2 * radius * np.ones(len(position)), 2 * radius * np.ones(len(position)),
                                        np.zeros(len(position)), units="xy", offsets=position[:, :2],
                                        offset_transform=ax.transData, facecolors="C0", edgecolors="none"))
    edges = np.asarray(edges)
    lengths = np.diag(edges) if edges.ndim == 2 else edges  # edges as box vectors or as lengths
    ax.set_xlim(0, float(lengths[0]))
    ax.set_ylim(0, float(lengths[1]))
    ax.set_aspect("equal")
    ax.set_title(f"positions at t = {t:.3g}", fontsize=10)
    ax.set_xlabel("x [L]")
    ax.set_ylabel("y [L]")


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def maxwell_boltzmann(v, temperature, mass, dim):
    a = mass / temperature
    if dim == 2:
        return a * v * np.exp(-0.5 * a * v * v)
    return np.sqrt(2 / np.pi) * a ** 1.5 * v * v * np.exp(-0.5 * a * v * v)


def draw_histogram(ax, f, name, dim, label, colour, theory=True):
    density = f[f"/results/{name}"][()]
    edges = f[f"/results/{name}_edges"][()]
    ax.stairs(density, edges, color=colour, label=label)
    stats = f[f"/results/speed_statistics/{name}"].attrs
    if theory and float(stats["temperature"]) > 0:
        v = np.linspace(0, edges[-1], 400)
        ax.plot(v, maxwell_boltzmann(v, float(stats["temperature"]), float(stats["mass"]), dim), "--",
                color=colour, lw=1)
    return stats


def plot_speed_distribution(files, output):
    f = files[0]
    dim = int(f["/parameters/system"].attrs["dimension"])
    n = int(f["/parameters/system"].attrs["count"])
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    draw_histogram(left, f, "speed_histogram_initial", dim, "t = 0", "C0", theory=False)
    left.set_title("initial speeds (all equal)")
    stats = draw_histogram(right, f, "speed_histogram", dim, "equilibrium (EDMD)", "C1")
    right.plot([], [], "--", color="C1", label="Maxwell-Boltzmann")
    snaps = int(f["/observables"].attrs["speed_snapshots"])
    right.set_title(f"{int(stats['samples'])} speeds from {snaps} snapshots", fontsize=10)
    lines = [f"{q}: {float(stats[q + '_speed']):.4f} (MB {float(stats['maxwell_boltzmann_' + q + '_speed']):.4f})"
             for q in ("mean", "rms", "most_probable")]
    lines.append(f"$\chi^2$ = {float(stats['chi_square']):.1f} (0.999: {float(stats['chi_square_critical_0999']):.1f})")
    right.text(0.98, 0.6, "\n".join(lines), transform=right.transAxes, ha="right", fontsize=8)
    label_speed_axes(left, right)
    right.legend(fontsize=8)
    fig.suptitle(f"speed distribution, {dim}D, N = {n}")
    save(fig, output)


def plot_mixture(files, output):
    dim = int(files[0]["/parameters/system"].attrs["dimension"])
    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    series = axes[0, 0]
    ratio = axes[0, 1]
    for k, f in enumerate(files):
        xi = float(f["/parameters/collision"].attrs["restitution"])
        time = f["/observables/kinetic_energy/time"][()]
        every = f["/observables/kinetic_energy/value"][()]
        species = f["/observables/kinetic_energy_by_species/value"][()]
        colour = f"C{k}"
        series.plot(time, every, "-", color=colour, label=f"all, $\\xi$ = {xi:g}")
        series.plot(time, species[:, 0], "--", color=colour, label=f"light, $\\xi$ = {xi:g}")
        series.plot(time, species[:, 1], ":", color=colour, label=f"heavy, $\\xi$ = {xi:g}")
        ratio.plot(time, species[:, 1] / species[:, 0], "-", color=colour, label=f"$\\xi$ = {xi:g}")
    series.set_xlabel("t [T]")
    series.set_ylabel("mean kinetic energy per particle [M L2 T-2]")
    series.set_yscale("log")
    series.legend(fontsize=7, ncol=2)
    ratio.axhline(1.0, color="k", lw=0.8)
    ratio.set_xlabel("t [T]")
    ratio.set_ylabel("heavy / light mean kinetic energy")
    ratio.legend(fontsize=8)
    for s, name in enumerate(("light", "heavy")):
        ax = axes[1, s]
        draw_histogram(ax, files[0], f"speed_histogram_initial_{name}", dim, "t = 0", "grey", theory=False)
        lines = []
        for k, f in enumerate(files):
            xi = float(f["/parameters/collision"].attrs["restitution"])
            stats = draw_histogram(ax, f, f"speed_histogram_{name}", dim, f"sampled, $\\xi$ = {xi:g}", f"C{k}")
            lines.append(f"$\\xi$ = {xi:g}: mean speed {float(stats['mean_speed']):.3f}, "
                         f"mean E {float(stats['mean_kinetic_energy']):.4f}")
        ax.set_title(f"{name} (m = {float(stats['mass']):g}); dashed: Maxwell-Boltzmann", fontsize=9)
        ax.text(0.98, 0.55, "\n".join(lines), transform=ax.transAxes, ha="right", fontsize=7)
        label_speed_axes(ax)
        ax.legend(fontsize=7)
    f = files[0]
    fig.suptitle(f"two-mass mixture, {dim}D, N = {int(f['/parameters/system'].attrs['count'])}")
    save(fig, output)


def plot_scattering(files, output):
    f = files[0]
    ratio = f["/results/impact_parameter_ratio"][()]
    fig, ax = plt.subplots(figsize=(6.4, 4.5))
    ax.plot(ratio, f["/results/scattering_angle"][()], "o", ms=4, label="granflow EDMD")
    if "analytic_curve_scattering_angle" in f["/results"]:
        ax.plot(f["/results/analytic_curve_impact_parameter_ratio"][()],
                f["/results/analytic_curve_scattering_angle"][()], "-", label="analytic")
    else:
        ax.plot(ratio, f["/results/scattering_angle_analytic"][()], "-", label="analytic (at the scan's points)")
    ax.set_xlabel("$b / R_{12}$")
    ax.set_ylabel("scattering angle [rad]")
    xi = float(f["/parameters/collision"].attrs["restitution"])
    ax.set_title(f"scattering off a heavy disk, $\\xi$ = {xi:g}", fontsize=10)
    ax.legend()
    save(fig, output)


def plot_crater(files, output):
    from matplotlib.collections import EllipseCollection
    f = files[0]
    position = f["/particles/all/position/value"][()]
    radius = f["/particles/all/radius"][()]
    species = f["/particles/all/species"][()]
    threshold = float(f["/parameters/crater"].attrs["displacement_threshold"]) * float(
        f["/parameters/derived"].attrs["bed_radius"])
    first, last = position[0], position[-1]
    moved = np.linalg.norm(last - first, axis=1) > threshold
    fig = plt.figure(figsize=(13, 4.6))
    for k, (frame, title) in enumerate(((first, "before"), (last, "after"))):
        ax = fig.add_subplot(1, 3, k + 1)
        colours = np.where(species == 1, "C3", np.where(moved & (k == 1), "C1", "C0"))
        # Widths in data units: the disks are drawn at their true size.
        ax.add_collection(EllipseCollection(2 * radius, 2 * radius, np.zeros_like(radius), units="xy",
                                            offsets=frame, transOffset=ax.transData, facecolors=colours,
                                            edgecolors="none"))
        ax.set_xlim(0, 1)
        ax.set_ylim(0, 1)
        ax.set_aspect("equal")
        ax.set_xlabel("x [L]")
        ax.set_ylabel("y [L]")
        t = f["/particles/all/position/time"][()][0 if k == 0 else -1]
        ax.set_title(f"{title} (t = {t:.3g})" + (f": crater {int(moved[species == 0].sum())} disks" if k else ""),
                     fontsize=10)
    ax = fig.add_subplot(1, 3, 3)
    time = f["/observables/crater_size/time"][()]
    ax.plot(time, f["/observables/crater_size/value"][()], "C0", label="crater size [disks]")
    r0 = float(f["/parameters/derived"].attrs["bed_radius"])
    ax.plot(time, f["/observables/projectile_depth/value"][()] / r0, "C3", label="projectile depth [bed radii]")
    ax.set_xlabel("t [T]")
    ax.set_ylabel("crater size [disks], projectile depth [bed radii]")
    twin = ax.twinx()
    e = f["/observables/kinetic_energy/value"][()]
    twin.semilogy(time, e / e[0], "C2", label="kinetic energy / initial (right)")
    twin.set_ylabel("kinetic energy / initial", color="C2")
    handles = ax.get_legend_handles_labels()[0] + twin.get_legend_handles_labels()[0]
    ax.legend(handles, [h.get_label() for h in handles], fontsize=7, loc="center right")
    save(fig, output)


def plot_granular_viscosity_sweep(files, output):
    """Kinetic viscosity of sheared granular SRD against the rotation angle
    (one summary per n0): measured, the granular theory and Kikuchi's at each
    point's measured temperature, and the relative deviations from both."""
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 4.6))
    for k, f in enumerate(files):
        summary = f["/summary"]
        alpha = np.array([float(text(v)) for v in summary["srd.rotation_angle"][()]])
        order = np.argsort(alpha)
        alpha = alpha[order]
        pick = lambda name: summary[name][()][order]
        measured, error = pick("viscosity_kinetic_mean_mean"), np.nan_to_num(pick("viscosity_kinetic_mean_stderr"))
        if "viscosity_kinetic_stderr_mean" in summary:
            error = np.hypot(error, pick("viscosity_kinetic_stderr_mean"))  # the runs' own block errors
        granular, elastic = pick("viscosity_granular_theory_mean"), pick("viscosity_elastic_theory_mean")
        runs = sorted(glob.glob(os.path.join(os.path.dirname(f.filename), "p*_r*.h5md")))
        n0 = f"file {k}"
        if runs:
            with h5py.File(runs[0], "r") as run:
                n0 = int(run["/parameters/srd"].attrs["particles_per_cell"])
        colour = f"C{k}"
        left.errorbar(alpha, measured, yerr=error, fmt="o", color=colour, capsize=3, label=f"measured, n0 = {n0}")
        left.plot(alpha, granular, "-", color=colour, lw=1, label="granular theory at the measured kT" if k == 0 else None)
        left.plot(alpha, elastic, ":", color=colour, lw=1, label="Kikuchi et al. 2003 at that kT" if k == 0 else None)
        right.errorbar(alpha, 100 * (measured - granular) / granular, yerr=100 * error / granular, fmt="o-",
                       color=colour, capsize=3, label=f"from the granular theory, n0 = {n0}")
        right.plot(alpha, 100 * (measured - elastic) / elastic, "s:", mfc="none", color=colour,
                   label=f"from Kikuchi's, n0 = {n0}")
    left.set_yscale("log")
    left.set_xlabel(r"rotation angle $\alpha$ [deg]")
    left.set_ylabel(r"kinetic viscosity $\nu_{kin}$ [L2 T-1]")
    left.legend(fontsize=8)
    right.axhline(0.0, color="k", lw=0.8)
    right.set_xlabel(r"rotation angle $\alpha$ [deg]")
    right.set_ylabel("relative deviation [%]")
    right.legend(fontsize=8)
    fig.suptitle("granular SRD under shear, 2D, no thermostat (heating = dissipation)", fontsize=11)
    save(fig, output)


def plot_sweep(files, output, x_key=None, y_names=None, logx=False):
    f = files[0]
    if "viscosity_granular_theory_mean" in f["/summary"] and x_key is None and not y_names:
        return plot_granular_viscosity_sweep(files, output)
    swept = [text(k) for k in f["/parameters/swept_keys"][()]]
    summary = f["/summary"]
    x_key = x_key or swept[0]
    if x_key not in summary:
        sys.exit(f"plot.py: '{x_key}' is not a swept key; swept: {', '.join(swept)}")
    x = np.array([float(text(v)) for v in summary[x_key][()]])
    params = f["/parameters"]
    ordered = [text(k) for k in params["summary"][()]] if "summary" in params else sorted(
        k[:-5] for k in summary if k.endswith("_mean"))
    units = dict(zip(ordered, [text(u) for u in params["summary_units"][()]])) if "summary_units" in params else {}
    key_units = (dict(zip(swept, [text(u) for u in params["swept_key_units"][()]]))
                 if "swept_key_units" in params else {})
    bracket = lambda u: "" if u in ("", "1") else f" [{u}]"
    names = y_names or [n for n in ordered if not (n.endswith("_theory") and n[:-7] in ordered)]
    others = [k for k in swept if k != x_key]
    groups = {}
    for row in range(len(x)):
        label = ", ".join(f"{k} = {text(summary[k][()][row])}" for k in others)
        groups.setdefault(label, []).append(row)
    fig, axes = plt.subplots(len(names), 1, figsize=(6.4, 3.6 * len(names)), squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        mean = summary[f"{name}_mean"][()]
        err = np.nan_to_num(summary[f"{name}_stderr"][()])
        for label, rows in groups.items():
            rows = sorted(rows, key=lambda r: x[r])
            if name == "eggers_flux_B":
                rows = [r for r in rows if mean[r] != 0.0]  # 0: too few crossings to fit
            ax.errorbar(x[rows], mean[rows], yerr=err[rows], fmt="o", capsize=3, label=label or "measured")
            if f"{name}_theory_mean" in summary:
                ax.plot(x[rows], summary[f"{name}_theory_mean"][()][rows], "k--",
                        label=f"theory{', ' + label if label else ''}")
        ax.set_xlabel(x_key + bracket(key_units.get(x_key, "")))
        ax.set_ylabel(name + bracket(units.get(name, "")))
        if logx:
            ax.set_xscale("log")
        if name == "eggers_flux_B":
            # Eggers (1999): equal sharing is stable while the flux model's B < 4.
            ax.axhline(4.0, color="k", lw=0.8, ls=":", label="B = 4: equal sharing stable below")
            ax.legend(fontsize=8)
        if len(groups) > 1 or f"{name}_theory_mean" in summary:
            ax.legend(fontsize=8)
    runs = summary["runs"][()]
    scenario = text(f["/parameters"].attrs["swept_scenario"])
    axes[0, 0].set_title(f"{scenario} sweep: mean $\\pm$ standard error over {int(runs.max())} runs per point",
                         fontsize=10)
    save(fig, output)


def series(f, name):
    return f[f"/observables/{name}/time"][()], f[f"/observables/{name}/value"][()]


def standard_error(f, name):
    """The standard error of an ensemble's mean series (run.runs > 1), or None."""
    return f[f"/observables/{name}_stderr/value"][()] if f"{name}_stderr" in f["/observables"] else None


def runs_of(f):
    return int(f["/observables"].attrs.get("runs", 1))


def plot_msd(files, output):
    f = files[0]
    scenario = scenario_of(f)
    has_eb = "ergodicity_breaking" in f["/observables"]
    fig, axes = plt.subplots(1, 3 if has_eb else 2, figsize=(16 if has_eb else 11, 4.6))
    left, middle = axes[0], axes[1]
    t, msd = series(f, "msd")
    _, err = series(f, "msd_stderr")
    _, theory = series(f, "msd_theory")
    left.errorbar(t, msd, yerr=np.nan_to_num(err), fmt="o", ms=3, capsize=2, label="ensemble MSD")
    left.loglog(t, theory, "k--", label="theory")
    if "time_averaged_msd" in f["/observables"]:
        lag, tamsd = series(f, "time_averaged_msd")
        left.loglog(lag, tamsd, "s", ms=3, mfc="none", label="time-averaged MSD (against the lag)")
    left.set_xlabel("t, or the lag of the time average [T]")
    left.set_ylabel("MSD" + unit_of(f, "/observables/msd/value"))
    derived = f["/parameters/derived"].attrs
    if scenario == "brownian_edmd":
        xi = float(f["/parameters/collision"].attrs["restitution"])
        title = (f"event-driven gas, $\\xi$ = {xi:g}: slope over last decade "
                 f"{float(f['/observables'].attrs['long_time_slope']) / (6 * float(derived['enskog_diffusivity0'])):.3f}"
                 " x 6 D0")
    else:
        title = (f"{scenario}: $\\gamma_0$ = {float(derived['gamma0']):.3g}, D0 = {float(derived['diffusivity0']):.3g}, "
                 f"$\\tau_0$ = {float(derived['tau0']):.3g}")
    left.set_title(title, fontsize=9)
    left.legend(fontsize=8)
    t, diffusivity = series(f, "diffusivity")
    middle.loglog(t, diffusivity, "o", ms=3, label="from the MSD: D = (1/2d) dMSD/dt")
    if "diffusivity_theory" in f["/observables"]:
        middle.loglog(*series(f, "diffusivity_theory"), "k--", label="theory (from its MSD)")
    middle.set_xlabel("t [T]")
    middle.set_ylabel("diffusivity D(t)" + unit_of(f, "/observables/diffusivity/value"))
    middle.legend(fontsize=8)
    if has_eb:
        right = axes[2]
        lag, eb = series(f, "ergodicity_breaking")
        right.semilogx(lag, eb, "^", ms=3, mfc="none", label="EB")
        right.axhline(0.0, color="k", lw=0.8)
        right.set_xlabel("lag [T]")
        right.set_ylabel("ergodicity breaking parameter EB (dimensionless)")
        right.set_title("EB = <(time-averaged MSD)^2> / <time-averaged MSD>^2 - 1: 0 when ergodic", fontsize=8)
    save(fig, output)


def draw_density_slice(ax, f):
    """The last density field (/fields/density) in the plane z = L_z/2 (3D) or whole (2D)."""
    if "fields" not in f or "density" not in f["/fields"]:
        ax.set_visible(False)
        return
    group = f["/fields/density"]
    value, t = group["value"][-1], group["time"][-1]
    plane = value[value.shape[0] // 2] if value.ndim == 3 else value
    image = ax.imshow(plane, origin="lower", cmap="viridis")
    plt.colorbar(image, ax=ax, label="particles per cell")
    where = f", z = {value.shape[0] // 2}" if value.ndim == 3 else ""
    ax.set_title(f"density, t = {t:.3g}{where}", fontsize=10)
    ax.set_xlabel("x [cells]")
    ax.set_ylabel("y [cells]")


def plot_srd_viscosity(files, output):
    f = files[0]
    obs = f["/observables"]
    derived = f["/parameters/derived"].attrs
    has_fields = "fields" in f and "density" in f["/fields"]
    has_band = "band_contrast" in obs
    granular = "viscosity_granular_theory" in obs.attrs and float(f["/parameters/srd"].attrs["restitution"]) < 1
    columns = 2 + has_fields
    fig, axes = plt.subplots(2 if has_band else 1, columns, figsize=(5.5 * columns, 8.8 if has_band else 4.4),
                             squeeze=False)
    left, right = axes[0, 0], axes[0, 1]
    if has_fields:
        draw_density_slice(axes[0, 2], f)
    for name, colour in (("viscosity_kinetic", "C0"), ("viscosity_collisional", "C1")):
        t, nu = series(f, name)
        left.plot(t, nu, "-", color=colour, label=name.replace("_", " ") + " (running mean)")
        if name == "viscosity_kinetic" and granular:
            # The fluid heats or cools to its steady temperature: theory at the one measured.
            left.axhline(float(obs.attrs["viscosity_granular_theory"]), color=colour, ls="--",
                         label=f"granular theory at measured kT_yy = {float(obs.attrs['temperature_yy_mean']):.3g}")
            left.axhline(float(obs.attrs["viscosity_elastic_theory"]), color=colour, ls=":",
                         label="Kikuchi et al. 2003 at that kT")
        else:
            left.axhline(float(derived[name + "_theory"]), color=colour, ls="--", label="Kikuchi et al. 2003")
    left.set_xlabel("t [T]")
    left.set_ylabel("kinematic viscosity [L2 T-1]")
    alpha = float(f["/parameters/srd"].attrs["rotation_angle"])
    dim = int(f["/parameters/system"].attrs["dimension"])
    title = f"SRD {dim}D, $\\alpha$ = {alpha:g} deg, n0 = {int(f['/parameters/srd'].attrs['particles_per_cell'])}"
    if granular and "effective_restitution_mean" in obs.attrs:
        title += f", $\\epsilon_{{eff}}$ = {float(obs.attrs['effective_restitution_mean']):.4f}"
    left.set_title(title, fontsize=10)
    left.legend(fontsize=7)
    t, T = series(f, "temperature")
    right.plot(t, T, "-", label="temperature (about the cells' means)")
    if "temperature_steady_theory" in derived:
        right.axhline(float(derived["temperature_steady_theory"]), color="C0", ls="--",
                      label="heating = dissipation (theory)")
    t, rate = series(f, "shear_rate_measured")
    right.plot(t, rate / float(f["/parameters/shear"].attrs["rate"]), "-", label="measured / imposed shear rate")
    right.set_xlabel("t [T]")
    right.set_ylabel("kT [M L2 T-2]; shear-rate ratio")
    if granular:
        right.set_yscale("log")
    right.legend(fontsize=8)
    if has_band:
        draw_shear_band(axes[1], f)
    save(fig, output)


def draw_shear_band(axes, f):
    """Density, velocity and temperature across the gradient (y) at a few
    times, and the band's width and contrast against time."""
    obs = f["/observables"]
    times = obs["density_profile/time"][()]
    density = obs["density_profile/value"][()]
    velocity = obs["velocity_profile/value"][()]
    temperature = obs["temperature_profile/value"][()]
    y = np.arange(density.shape[1]) + 0.5
    profiles, history = axes[0], axes[1]
    picks = sorted(set(np.linspace(0, len(times) - 1, 4).astype(int)))
    twin = profiles.twinx()
    for k, row in enumerate(picks):
        profiles.plot(y, density[row], "-", color=f"C{k}", label=f"density, t = {times[row]:.3g}")
        twin.plot(y, temperature[row], ":", color=f"C{k}")
    profiles.set_xlabel("y [cells]")
    profiles.set_ylabel("particles per cell (solid)")
    twin.set_ylabel("kT of the layer (dotted)")
    twin.set_yscale("log")
    profiles.legend(fontsize=7)
    history.semilogy(obs["band_contrast/time"][()], obs["band_contrast/value"][()], "o-", ms=3,
                     label="contrast: densest / thinnest layer")
    history.semilogy(obs["band_width/time"][()], obs["band_width/value"][()], "s-", ms=3,
                     label="width: layers above half the peak over the median [cells]")
    history.set_xlabel("t [T]")
    history.legend(fontsize=7)
    if len(axes) > 2:
        last = axes[2]
        last.plot(y, velocity[-1], "o-", ms=3, label=f"$v_x$, t = {times[-1]:.3g}")
        last.set_xlabel("y [cells]")
        last.set_ylabel("v_x [L T-1]")
        last.legend(fontsize=7)


def plot_gsrd_cooling(files, output):
    clustering = "correlation_length" in files[0]["/observables"]
    has_fields = "fields" in files[0] and "temperature" in files[0]["/fields"]
    rows = 2 + clustering + (clustering and has_fields)
    fig, axes = plt.subplots(rows, 3, figsize=(16, 4 * rows))
    labels = overlay_labels(files) if len(files) > 1 else [None]
    for k, (f, label) in enumerate(zip(files, labels)):
        tau = float(f["/parameters/derived"].attrs["haff_tau"])
        t, T = series(f, "granular_temperature")
        _, E = series(f, "convective_kinetic_energy")
        _, sigma = series(f, "density_std")
        _, a2 = series(f, "sonine_a2")
        _, mach = series(f, "mach_number")
        T0 = T[0]
        keep = t > 0
        colour = f"C{k}"
        ax = axes[0, 0]
        single = len(files) == 1
        if runs_of(f) > 1:
            label = f"{label or ''}{', ' if label else ''}mean of {runs_of(f)} runs"
            error = standard_error(f, "granular_temperature")
            ax.fill_between(t[keep], (T[keep] - 2 * error[keep]) / T0, (T[keep] + 2 * error[keep]) / T0,
                            color=colour, alpha=0.3, lw=0)
        ax.loglog(t[keep], T[keep] / T0, "o", ms=3, color=colour,
                  label="granular temperature T / T0" if single and runs_of(f) == 1 else label)
        ax.loglog(t[keep], E[keep] / T0, "s", ms=3, mfc="none", color=colour,
                  label="convective energy E_kin / T0" if single else None)
        ax.loglog(t[keep], 1 / (1 + t[keep] / tau) ** 2, "--", color="k" if single else colour, lw=0.8,
                  label=f"Haff, mean-field $\\tau$ = {tau:.3g}" if single else None)
        axes[0, 1].semilogx(t[keep], sigma[keep] / sigma[0], "o-", ms=3, color=colour, label=label)
        axes[1, 0].semilogx(t[keep], a2[keep], "o-", ms=3, color=colour, label=label)
        if "sonine_a2_hcs" in f["/observables"]:
            t_hcs, a2_hcs = series(f, "sonine_a2_hcs")
            axes[1, 0].semilogx(t_hcs[t_hcs > 0], a2_hcs[t_hcs > 0], "--", color=colour, lw=0.8,
                                label=r"hard spheres of $\epsilon_{eff}$ (van Noije-Ernst)" if k == 0 else None)
        axes[1, 1].loglog(t[keep], mach[keep], "o-", ms=3, color=colour, label=label)
    ax = axes[0, 0]
    ax.set_xlabel("t [T]")
    ax.set_ylabel("energy / kT0")
    ax.legend(fontsize=8)
    axes[0, 1].set_xlabel("t [T]")
    axes[0, 1].set_ylabel(r"$\sigma(\rho) / \sigma_0$ (particles per cell)")
    axes[1, 0].axhline(0.0, color="k", lw=0.8)
    axes[1, 0].set_xlabel("t [T]")
    axes[1, 0].set_ylabel("Sonine coefficient a2")
    axes[1, 1].axhline(1.0, color="k", lw=0.8)
    axes[1, 1].set_xlabel("t [T]")
    axes[1, 1].set_ylabel("global Mach number")
    for ax in (axes[0, 1], axes[1, 0], axes[1, 1]):
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    f = files[0]
    dim = int(f["/parameters/system"].attrs["dimension"])
    ax = axes[0, 2]
    if "velocity_distribution" in f["/observables"]:
        group = f["/observables/velocity_distribution"]
        bins, c_max = int(group.attrs["bins"]), float(group.attrs["c_max"])
        centres = (np.arange(bins) + 0.5) * c_max / bins
        times, values = group["time"][()], group["value"][()]
        for row, style in ((0, "o"), (len(times) - 1, "s")):
            ax.semilogy(centres, values[row], style, ms=3, mfc="none", label=f"t = {times[row]:.3g}")
        c = np.linspace(0.0, c_max, 400)
        x = c * c
        maxwell = 4 / np.sqrt(np.pi) * x * np.exp(-x) if dim == 3 else 2 * c * np.exp(-x)
        ax.semilogy(c, maxwell, "k-", lw=0.8, label="Maxwellian")
        last_a2 = series(f, "sonine_a2")[1][-1]
        sonine = maxwell * (1 + last_a2 * (x * x / 2 - (dim + 2) * x / 2 + dim * (dim + 2) / 8))
        ax.semilogy(c, np.clip(sonine, 1e-12, None), "r--", lw=0.8, label=f"Sonine, a2 = {last_a2:.3g} (last)")
        ax.set_ylim(max(1e-6, values[values > 0].min() / 2), 1.5)
        ax.set_xlabel(r"$c = |v - \langle v \rangle| / \sqrt{2 T_g / m}$")
        ax.set_ylabel("f(c)")
        ax.legend(fontsize=7)
    else:
        ax.set_visible(False)
    draw_density_slice(axes[1, 2], f)
    if clustering:
        draw_clustering(axes[2], files, labels)
    if clustering and has_fields:
        draw_local_fields(axes[3], f)
    eps = float(f["/parameters/srd"].attrs["restitution"])
    fig.suptitle(f"granular SRD cooling, $\\epsilon$ = {eps:g}" if len(files) == 1 else
                 f"granular SRD cooling, {len(files)} runs (distribution and slice: the first)")
    save(fig, output)


def draw_clustering(axes, files, labels):
    """S(k) at a few times (the first file), the correlation length and the
    largest cluster against time, and sigma(rho)^2 against the global Mach
    number (every file: Fig. 4.1 of the granular SRD study overlays three dt)."""
    f = files[0]
    obs = f["/observables"]
    times = obs["structure_factor/time"][()]
    values = obs["structure_factor/value"][()]
    k = obs["structure_factor_k/value"][()][-1]
    for n, row in enumerate(sorted(set(np.geomspace(1, len(times) - 1, 5).astype(int)))):
        axes[0].loglog(k, values[row], "o-", ms=3, color=plt.cm.viridis(n / 4), label=f"t = {times[row]:.3g}")
    axes[0].axhline(1.0, color="k", lw=0.8, ls=":", label="ideal gas")
    axes[0].set_xlabel("k [L-1]")
    axes[0].set_ylabel("structure factor S(k)")
    axes[0].legend(fontsize=7)
    mach_axis = axes[1].twinx()
    for n, (g, label) in enumerate(zip(files, labels)):
        colour = f"C{n}"
        t, length = series(g, "correlation_length")
        keep = t > 0
        axes[1].loglog(t[keep], length[keep], "o-", ms=3, color=colour, label=f"L(t) {label or ''}".strip())
        t_m, mach = series(g, "mach_number")
        mach_axis.loglog(t_m[t_m > 0], mach[t_m > 0], ":", color=colour)
        transition = g["/observables"].attrs.get("transition_time", np.nan)
        if np.isfinite(transition):
            axes[1].axvline(transition, color=colour, lw=0.8, ls="--")
        _, sigma = series(g, "density_std")
        _, mach_all = series(g, "mach_number")
        axes[2].loglog(mach_all[1:], sigma[1:] ** 2, "o-", ms=3, color=colour,
                       label=f"dt = {float(g['/parameters/srd'].attrs['time_step']):g}" + (f", {label}" if label else ""))
    mach_axis.axhline(1.0, color="grey", lw=0.8)
    mach_axis.set_ylabel("global Mach number (dotted)")
    axes[1].set_xlabel("t [T]")
    axes[1].set_ylabel("correlation length L = 2 pi <k>^-1 [cells]")
    exponent = obs.attrs.get("cooling_exponent", np.nan)
    if np.isfinite(exponent):
        axes[1].set_title(f"after M = 1 (dashed): T ~ t^{exponent:.2f}", fontsize=9)
    axes[1].legend(fontsize=7)
    m = np.geomspace(0.3, 10, 50)
    _, mach_first = series(f, "mach_number")
    _, sigma_first = series(f, "density_std")
    nearest = np.argmin(np.abs(np.log(np.maximum(mach_first[1:], 1e-12))))
    reference = sigma_first[1:][nearest] ** 2 / mach_first[1:][nearest] ** 2
    axes[2].loglog(m, reference * m ** 2, "k-", lw=0.8, label=r"$\propto M^2$")
    axes[2].loglog(m, reference * m ** 3, "k:", lw=0.8, label=r"$\propto M^3$")
    axes[2].axvline(1.0, color="grey", lw=0.8)
    axes[2].set_xlabel("global Mach number M")
    axes[2].set_ylabel(r"$\sigma(\rho)^2$ [particles per cell]$^2$")
    axes[2].legend(fontsize=7)


def draw_local_fields(axes, f):
    """The last fields in the plane z = L_z/2 (3D): temperature, local Mach
    number |V| / sqrt(kT/m) and the largest clusters' density (Fig. 3.10)."""
    fields = f["/fields"]
    density, temperature, velocity = (fields[name]["value"][-1] for name in ("density", "temperature", "velocity"))
    t = fields["temperature"]["time"][-1]
    middle = lambda a: a[a.shape[0] // 2] if density.ndim == 3 else a
    speed = np.linalg.norm(velocity, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        mach = np.where(temperature > 0, speed / np.sqrt(temperature), np.nan)
    for ax, value, name, log in ((axes[0], temperature, "kT", True), (axes[1], mach, "local Mach number", True),
                                 (axes[2], density, "particles per cell", True)):
        plane = middle(value)
        positive = plane[np.isfinite(plane) & (plane > 0)]
        norm = matplotlib.colors.LogNorm(positive.min(), positive.max()) if log and positive.size else None
        image = ax.imshow(np.where(plane > 0, plane, np.nan), origin="lower", cmap="magma" if ax is axes[0] else "viridis",
                          norm=norm)
        plt.colorbar(image, ax=ax, label=name)
        ax.set_title(f"{name}, t = {t:.3g}" + (", z = middle" if density.ndim == 3 else ""), fontsize=10)
        ax.set_xlabel("x [cells]")
        ax.set_ylabel("y [cells]")


def plot_srd_poiseuille(files, output):
    f = files[0]
    obs = f["/observables"]
    g = float(f["/parameters/derived"].attrs["acceleration"])
    nu_theory = float(obs.attrs["viscosity_theory"])
    nu = float(obs.attrs["viscosity_measured_mean"])
    velocity = obs["velocity_profile/value"][()].mean(axis=0)
    density = obs["density_profile/value"][()].mean(axis=0)
    temperature = obs["temperature_profile/value"][()].mean(axis=0)
    layers = len(velocity)
    y = np.arange(layers) + 0.5
    fine = np.linspace(0, layers, 200)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.4))
    left.plot(y, velocity, "o", ms=4, label="measured (mean of the blocks)")
    left.plot(fine, g / (2 * nu_theory) * fine * (layers - fine), "k--",
              label=f"no slip, $\\nu$ = {nu_theory:.4g} (Kikuchi et al.)")
    left.plot(fine, g / (2 * nu) * fine * (layers - fine), "C1-", lw=0.8, label=f"curvature fit: $\\nu$ = {nu:.4g}")
    left.set_xlabel("y [cells]")
    left.set_ylabel("v_x [L T-1]")
    left.legend(fontsize=8)
    right.plot(y, density / density.mean(), "o-", ms=3, label="density / mean")
    right.plot(y, temperature, "s-", ms=3, label="kT of the layer")
    right.set_xlabel("y [cells]")
    right.legend(fontsize=8)
    fig.suptitle("SRD Poiseuille flow between no-slip walls")
    save(fig, output)


def plot_gsrd_shaken(files, output):
    f = files[0]
    obs = f["/observables"]
    n0 = float(f["/parameters/srd"].attrs["particles_per_cell"])
    dim = int(f["/parameters/system"].attrs["dimension"])
    has_fields = "fields" in f and "density" in f["/fields"]
    fig, axes = plt.subplots(2, 2, figsize=(12, 8.5))
    ax = axes[0, 0]
    if "density_profile" in obs:
        density = obs["density_profile/value"][()]
        temperature = obs["temperature_profile/value"][()]
        times = obs["density_profile/time"][()]
        z = np.arange(density.shape[1]) + 0.5
        for row in sorted({0, len(times) // 2, len(times) - 1}):
            ax.plot(density[row] / n0, z, "-", label=f"density / n0, t = {times[row]:.4g}")
        twin = ax.twiny()
        twin.plot(temperature[-1], z, "k--", lw=1, label=f"kT, t = {times[-1]:.4g}")
        twin.set_xlabel("kT of the layer [M L2 T-2] (dashed)")
        ax.set_xlabel("density / n0 (particles per cell / n0)")
        ax.set_ylabel("height [cells]")
        ax.legend(fontsize=7, loc="upper right")
        ax.set_title("profiles: a dense layer over a hot one", fontsize=10)
    t, injected = series(f, "energy_injected")
    _, dissipated = series(f, "energy_dissipated")
    _, kinetic = series(f, "kinetic_energy")
    _, potential = series(f, "potential_energy")
    _, error = series(f, "energy_balance_error")
    ax = axes[0, 1]
    ax.plot(t, injected, label="injected by the floor")
    ax.plot(t, dissipated, label="dissipated in collisions")
    ax.plot(t, kinetic + potential - kinetic[0] - potential[0], label="change of kinetic + potential energy")
    ax.plot(t, injected - dissipated, "k:", label="injected - dissipated")
    ax.set_xlabel("t [T]")
    ax.set_ylabel("energy [M L2 T-2]")
    ax.set_title(f"largest balance error {np.abs(error).max():.2g}", fontsize=10)
    ax.legend(fontsize=7)
    ax = axes[1, 0]
    _, peak = series(f, "peak_cell_density")
    _, height = series(f, "centre_of_mass_height")
    ax.semilogy(t, peak, "o-", ms=3, label="peak cell density / n0")
    ax.set_xlabel("t [T]")
    ax.set_ylabel("peak cell density / n0 (growing: collapse)")
    twin = ax.twinx()
    twin.plot(t, height, "C1-", label="centre of mass height")
    twin.set_ylabel("centre of mass height [cells] (orange)")
    ax.legend(fontsize=7, loc="upper left")
    ax = axes[1, 1]
    if has_fields:
        group = f["/fields/density"]
        value, when = group["value"][-1], group["time"][-1]
        side = value[:, value.shape[1] // 2, :] if value.ndim == 3 else value
        image = ax.imshow(side, origin="lower", cmap="viridis", aspect="auto")
        plt.colorbar(image, ax=ax, label="particles per cell")
        ax.set_title(f"density, side view, t = {when:.4g}" + (", y = L_y/2" if value.ndim == 3 else ""), fontsize=10)
        ax.set_xlabel("x [cells]")
        ax.set_ylabel("height [cells]")
    else:
        ax.set_visible(False)
    amplitude = float(f["/parameters/shaking"].attrs["amplitude"])
    frequency = float(f["/parameters/shaking"].attrs["frequency"])
    eps = float(f["/parameters/srd"].attrs["restitution"])
    fig.suptitle(f"granular SRD shaken from below ({dim}D): A = {amplitude:g}, f = {frequency:g}, $\\epsilon$ = {eps:g}")
    save(fig, output)


def plot_shaken_bed(files, output):
    f = files[0]
    t, a = series(f, "asymmetry")
    _, lr = series(f, "flux_left_to_right")
    _, rl = series(f, "flux_right_to_left")
    _, kinetic = series(f, "kinetic_energy")
    _, potential = series(f, "potential_energy")
    _, elastic = series(f, "elastic_energy")
    _, injected = series(f, "energy_injected")
    _, dissipated = series(f, "energy_dissipated")
    n = int(f["/parameters/system"].attrs["count"])
    fig, (left, middle, right) = plt.subplots(1, 3, figsize=(16, 4.4))
    left.plot(t, a, "-", lw=1)
    left.axhline(0.0, color="k", lw=0.8)
    left.fill_between(t, -1 / np.sqrt(n), 1 / np.sqrt(n), color="0.85", label="1/sqrt(N): equal sharing's spread")
    left.set_ylim(-1.05, 1.05)
    left.set_xlabel("t [T]")
    left.set_ylabel("asymmetry (N_L - N_R) / N")
    left.legend(fontsize=8)
    middle.step(t, lr, where="post", label="left to right")
    middle.step(t, rl, where="post", label="right to left")
    middle.set_xlabel("t [T]")
    middle.set_ylabel("crossings per output interval")
    middle.legend(fontsize=8)
    total = kinetic + potential + elastic
    right.plot(t, total - total[0], label="change of kinetic + potential + elastic energy")
    right.plot(t, injected - dissipated, "k:", label="injected by the floor - dissipated")
    right.plot(t, injected, label="injected")
    right.plot(t, dissipated, label="dissipated")
    right.set_xlabel("t [T]")
    right.set_ylabel("energy [M L2 T-2]")
    right.legend(fontsize=7)
    amplitude = float(f["/parameters/shaking"].attrs["amplitude"])
    frequency = float(f["/parameters/shaking"].attrs["frequency"])
    fig.suptitle(f"shaken bed, N = {n}, A = {amplitude:g}, f = {frequency:g}")
    save(fig, output)
    divider = f["/parameters/divider"].attrs
    box = f["/parameters/system"].attrs["box"]
    position = float(divider["position"]) or 0.5 * box[0]
    draw_bed(f, os.path.splitext(output)[0] + "_bed.png", ["_left", "_right"],
             divider=(position, float(divider["height"])))


def draw_side_view(ax, f, divider=None):
    """The last particle frame seen along y: each sphere a disc at (x, z)."""
    from matplotlib.collections import EllipseCollection
    box = f["/parameters/system"].attrs["box"]
    if "/particles/all/position" not in f:
        ax.text(0.5, 0.5, "no particle frame (output.positions = none)", ha="center", transform=ax.transAxes)
        return
    x = f["/particles/all/position/value"][-1]
    d = 2 * f["/particles/all/radius"][()]
    ax.add_collection(EllipseCollection(d, d, np.zeros_like(d), offsets=x[:, [0, 2]], units="xy",
                                        transOffset=ax.transData, facecolors="C0", edgecolors="k", linewidths=0.2,
                                        alpha=0.7))
    if divider:
        ax.plot([divider[0], divider[0]], [0, divider[1]], "k-", lw=2)
    ax.set_xlim(0, box[0])
    ax.set_ylim(0, min(box[2], max(1.2 * x[:, 2].max(), 1.0)))
    ax.set_aspect("equal")
    ax.set_xlabel("x [L]")
    ax.set_ylabel("z [L]")
    ax.set_title(f"side view at t = {f['/particles/all/velocity/time'][-1]:.4g}", fontsize=9)


def draw_bed(f, output, suffixes, divider=None, title=None):
    """Side view of the last frame and the time-averaged profiles against height."""
    obs = f["/observables"]
    fig, (view, packing, temperature) = plt.subplots(1, 3, figsize=(16, 4.4),
                                                     gridspec_kw={"width_ratios": [1.6, 1, 1]})
    draw_side_view(view, f, divider)
    if "height_profile_layer" not in obs.attrs:
        packing.text(0.5, 0.5, "no time-averaged profiles", ha="center", transform=packing.transAxes)
        save(fig, output)
        return
    layer = float(obs.attrs["height_profile_layer"])
    top = layer
    for suffix in suffixes:
        phi = f[f"/results/packing_fraction_profile_mean{suffix}"][()]
        t = f[f"/results/temperature_profile_mean{suffix}"][()]
        z = (np.arange(len(phi)) + 0.5) * layer
        label = suffix.strip("_") or "bed"
        packing.plot(phi, z, "-o", ms=3, label=label)
        filled = t > 0
        temperature.plot(t[filled], z[filled], "-o", ms=3, label=label)
        if filled.any():
            top = max(top, z[filled].max() + 2 * layer)
    for ax, name in ((packing, "packing fraction"), (temperature, "granular temperature [M L2 T-2]")):
        ax.set_xlabel(name)
        ax.set_ylabel("height z [L]")
        ax.set_ylim(0, top)
        ax.legend(fontsize=8)
    temperature.set_xscale("log")
    samples = int(obs.attrs["height_profile_samples"])
    start = float(obs.attrs["height_profile_average_from"])
    packing.set_title(f"time average of {samples} samples from t = {start:g}", fontsize=9)
    if title:
        fig.suptitle(title)
    save(fig, output)


def plot_vibrated_bed(files, output):
    f = files[0]
    n = int(f["/parameters/system"].attrs["count"])
    amplitude = float(f["/parameters/shaking"].attrs["amplitude"])
    frequency = float(f["/parameters/shaking"].attrs["frequency"])
    draw_bed(f, output, [""], title=f"vibrated bed, N = {n}, A = {amplitude:g}, f = {frequency:g}")


PLOTTERS = {"haff_cooling": plot_haff,
            "speed_distribution": plot_speed_distribution,
            "mixture": plot_mixture,
            "scattering": plot_scattering,
            "crater_impact": plot_crater,
            "langevin_msd": plot_msd,
            "udsbm_msd": plot_msd,
            "brownian_edmd": plot_msd,
            "srd_viscosity": plot_srd_viscosity,
            "srd_poiseuille": plot_srd_poiseuille,
            "gsrd_shaken": plot_gsrd_shaken,
            "shaken_bed": plot_shaken_bed,
            "vibrated_bed": plot_vibrated_bed,
            "gsrd_cooling": plot_gsrd_cooling}


def srd_collision_factor(n0):
    return n0 - 1.0 + np.exp(-n0)


def srd_kinetic_viscosity(dimension, n0, alpha, temperature, dt):
    """Kikuchi et al. 2003, as systems/srd/srd_theory.hpp (plot_test checks the two agree)."""
    f = srd_collision_factor(n0)
    bracket = (n0 / (f * (1 - np.cos(2 * alpha))) if dimension == 2 else
               5 * n0 / (f * (4 - 2 * np.cos(alpha) - 2 * np.cos(2 * alpha)))) - 0.5
    return temperature * dt * bracket


def srd_collisional_viscosity(dimension, n0, alpha, dt):
    return (1 - np.cos(alpha)) * srd_collision_factor(n0) / n0 / ((12 if dimension == 2 else 18) * dt)


def plot_srd_viscosity_theory(output, n0, dt, dimension):
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    temperature = np.geomspace(1e-4, 10, 200)
    for k, degrees in enumerate((10, 20, 45, 90, 130)):
        alpha = np.radians(degrees)
        colour = f"C{k}"
        ax.loglog(temperature, srd_kinetic_viscosity(dimension, n0, alpha, temperature, dt), "-", color=colour,
                  label=f"kinetic, $\\alpha$ = {degrees} deg")
        ax.axhline(srd_collisional_viscosity(dimension, n0, alpha, dt), color=colour, ls="--", lw=0.8)
    ax.plot([], [], "k--", lw=0.8, label="collisional (same colours)")
    ax.set_xlabel("kT [M L2 T-2] (m = 1)")
    ax.set_ylabel("kinematic viscosity [L2 T-1]")
    ax.set_title(f"SRD {dimension}D, n0 = {n0:g}, $\\Delta t$ = {dt:g}: viscosity as the fluid cools", fontsize=10)
    ax.legend(fontsize=7)
    save(fig, output)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("files", nargs="*", help="granflow H5MD result files (several: overlaid where it makes sense)")
    parser.add_argument("-o", "--output", help="figure file (default: first FILE with .png)")
    parser.add_argument("--x", help="sweep summaries: swept key on the x axis (default: the first)")
    parser.add_argument("--y", action="append", help="sweep summaries: observable to draw (repeatable; default: all)")
    parser.add_argument("--logx", action="store_true", help="sweep summaries: logarithmic x axis")
    parser.add_argument("--srd-viscosity-theory", action="store_true",
                        help="no files: SRD's kinetic and collisional viscosity against temperature")
    parser.add_argument("--n0", type=float, default=5.0, help="--srd-viscosity-theory: particles per cell")
    parser.add_argument("--dt", type=float, default=1.0, help="--srd-viscosity-theory: time step")
    parser.add_argument("--dimension", type=int, default=3, choices=(2, 3), help="--srd-viscosity-theory: 2 or 3")
    args = parser.parse_args()
    if args.srd_viscosity_theory:
        return plot_srd_viscosity_theory(args.output or "srd_viscosity_theory.png", args.n0, args.dt, args.dimension)
    if not args.files:
        parser.error("give result files (or --srd-viscosity-theory)")
    first = args.files[0]
    output = args.output or os.path.splitext(first)[0] + ".png"
    files = [h5py.File(name, "r") for name in args.files]
    try:
        scenario = scenario_of(files[0])
        if scenario == "sweep":
            plot_sweep(files, output, args.x, args.y, args.logx)
        elif scenario in PLOTTERS:
            PLOTTERS[scenario](files, output)
        else:
            sys.exit(f"plot.py: no figure defined for scenario '{scenario}'")
    finally:
        for f in files:
            f.close()


if __name__ == "__main__":
    main()
