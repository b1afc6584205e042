#!/usr/bin/python3
"""Runs every command of docs/figures.md at the reduced size its row gives.

A row of a figure table whose "Command" cell holds `granflow run ...`,
`granflow sweep ...` or `plot.py ...` (in backticks, run in order from one
scratch directory) is a figure granflow offers; its "Reduced" cell holds the
`--set key=value` overrides (in backticks) that make it small. They are
added to every `granflow run` of the row, and to the [set] table of every
swept file (a reduced copy of it, its scenario_file made absolute). Every
command must exit 0 and every plot.py must write its figure.

    figures_test.py GRANFLOW SOURCE_DIR [--only FIGURE-ID ...]
Skips (exit 77) where /usr/bin/python3 lacks h5py or matplotlib.
"""

import glob
import importlib.util
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time
import tomllib
import traceback


def rows(markdown):
    """(figure id, command cell, reduced cell) of every table row with a command."""
    study = None
    for line in markdown.splitlines():
        heading = re.match(r"^## .*\((\d{3})\)", line)
        if heading:
            study = heading.group(1)
        if not line.startswith("|") or study is None:
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 5 or cells[0] in ("Figure", "---") or set(cells[0]) <= set("-: "):
            continue
        commands = re.findall(r"`([^`]+)`", cells[2])
        if not any(c.startswith(("granflow ", "plot.py ")) for c in commands):
            continue
        reduced = re.findall(r"`([^`]+)`", cells[3])
        yield f"{study}:{cells[0]}", commands, " ".join(reduced)


def toml_value(text):
    """A --set value as TOML (numbers, booleans, arrays and quoted strings pass as they are)."""
    try:
        tomllib.loads(f"x = {text}")
        return text
    except tomllib.TOMLDecodeError:
        return '"' + text.replace('"', '\\"') + '"'


def overrides(reduced):
    words = shlex.split(reduced)
    pairs = []
    for k, word in enumerate(words):
        if word == "--set":
            key, _, value = words[k + 1].partition("=")
            pairs.append((key, value))
    return pairs


def reduced_sweep(source, sweep, pairs, directory):
    """A copy of sweep file `sweep` with `pairs` in its [set] table."""
    path = os.path.join(source, sweep)
    with open(path, "rb") as f:
        parsed = tomllib.load(f)
    lines = []
    for key, value in parsed.items():
        if isinstance(value, dict):
            continue
        if key == "scenario_file":
            value = os.path.join(os.path.dirname(path), value)
        lines.append(f"{key} = {toml_literal(value)}")
    tables = {name: flatten(value) for name, value in parsed.items() if isinstance(value, dict)}
    base = tables.setdefault("set", {})
    for key, value in pairs:
        base[key] = tomllib.loads(f"x = {toml_value(value)}")["x"]
    for name, table in tables.items():
        lines.append(f"[{name}]")
        lines += [f'"{key}" = {toml_literal(value)}' for key, value in table.items()]
    out = os.path.join(directory, os.path.basename(sweep))
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")
    return out


def flatten(table, prefix=""):
    """{"a": {"b": 1}} as {"a.b": 1}: configuration keys written as nested tables."""
    out = {}
    for key, value in table.items():
        if isinstance(value, dict):
            out.update(flatten(value, f"{prefix}{key}."))
        else:
            out[f"{prefix}{key}"] = value
    return out


def toml_literal(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace('"', '\\"') + '"'
    if isinstance(value, list):
        return "[" + ", ".join(toml_literal(v) for v in value) + "]"
    return repr(value)


plot_module = None


def plot_in_process(source, arguments, directory):
    """tools/plot.py's main() on `arguments` (globs expanded as the shell
    would), in `directory`, in this process: importing matplotlib and h5py
    takes 1.5 s of each separate call, and the catalogue makes about fifty.
    (plot_test runs plot.py as a program.) Returns what went wrong, or None."""
    global plot_module
    if plot_module is None:
        spec = importlib.util.spec_from_file_location("granflow_plot", os.path.join(source, "tools/plot.py"))
        plot_module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(plot_module)
    words = []
    for word in arguments:
        matches = sorted(glob.glob(word, root_dir=directory)) if any(c in word for c in "*?[") else []
        words += matches or [word]
    saved = os.getcwd(), sys.argv
    os.chdir(directory)
    sys.argv = ["plot.py"] + words
    try:
        plot_module.main()
    except SystemExit as stop:
        if stop.code not in (None, 0):
            return f"exited with {stop.code}"
    except Exception:
        return "raised:\n" + traceback.format_exc()[-2000:]
    finally:
        os.chdir(saved[0])
        sys.argv = saved[1]
        plot_module.plt.close("all")
    return None


def run_row(granflow, source, figure, commands, reduced, scratch):
    directory = os.path.join(scratch, re.sub(r"[^A-Za-z0-9.]+", "_", figure))
    os.makedirs(directory, exist_ok=True)
    pairs = overrides(reduced)
    sets = " ".join(f"--set {shlex.quote(f'{k}={v}')}" for k, v in pairs)
    for command in commands:
        words = shlex.split(command)
        if words[0] == "granflow" and words[1] == "run":
            line = f"{shlex.quote(granflow)} run {shlex.quote(os.path.join(source, words[2]))} -q " + \
                   " ".join(shlex.quote(w) for w in words[3:]) + " " + sets
        elif words[0] == "granflow" and words[1] == "sweep":
            sweep = reduced_sweep(source, words[2], pairs, directory)
            line = f"{shlex.quote(granflow)} sweep {shlex.quote(sweep)} -q " + " ".join(shlex.quote(w) for w in words[3:])
        elif words[0] == "granflow":
            line = f"{shlex.quote(granflow)} " + " ".join(shlex.quote(w) for w in words[1:])
        elif words[0] == "plot.py":
            line = None
        else:
            continue
        started = time.time()
        if line is None:
            problem = plot_in_process(source, words[1:], directory)
            if problem:
                return f"`{command}` {problem}"
        else:
            done = subprocess.run(line, shell=True, cwd=directory, capture_output=True, text=True, timeout=900)
            if done.returncode != 0:
                return f"`{command}` exited with {done.returncode}:\n{done.stderr[-2000:]}"
        if words[0] == "plot.py":
            output = words[words.index("-o") + 1] if "-o" in words else None
            if output and not os.path.getsize(os.path.join(directory, output)):
                return f"`{command}` wrote an empty figure"
        print(f"  {time.time() - started:6.1f} s  {command}")
    return None


def main():
    granflow, source = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    only = sys.argv[sys.argv.index("--only") + 1:] if "--only" in sys.argv else None
    try:
        import h5py  # noqa: F401
        import matplotlib  # noqa: F401
    except ImportError:
        print("skipped: /usr/bin/python3 has no h5py or matplotlib (apt-get install python3-h5py python3-matplotlib)")
        return 77
    with open(os.path.join(source, "docs/figures.md")) as f:
        catalogue = list(rows(f.read()))
    if len(catalogue) < 30:
        print(f"FAIL: docs/figures.md lists only {len(catalogue)} figures with commands")
        return 1
    failures = 0
    with tempfile.TemporaryDirectory(prefix="granflow_figures_") as scratch:
        for figure, commands, reduced in catalogue:
            if only and figure not in only:
                continue
            print(f"{figure}: {reduced or 'full size'}")
            problem = run_row(granflow, source, figure, commands, reduced, scratch)
            if problem:
                failures += 1
                print(f"FAIL: {figure}: {problem}")
    print(f"{len(catalogue)} figures, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
