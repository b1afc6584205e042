#!/usr/bin/env python3
"""Every key of the soft-sphere and SRD scenarios, set to values a new user
or a fuzzer would try (wrong type, 0, negative, NaN, inf, 1e308, 5e-324,
empty and long arrays, bad wall tables) and to random numbers of any
magnitude and random arrays (seeded), on tiny runs with a time limit each. The oracle: the run ends with status 0, 2 or 3 within the limit, or
(a long run of accepted values) stops on SIGINT at the limit with a finite
state checkpointed; a message never is a library's (bad_alloc, map::at,
...); a run that exits 0 has finite observables and its particles in or
near the box.

  tests/cli/key_campaign.py GRANFLOW SCENARIOS_DIR [--sample N] [--seed S] [--limit SECONDS] [--jobs J]

--sample N picks N of the runs at random (seeded): the short variant CI runs.
Prints the counts per scenario and every failure; exits 1 on any failure.
"""
import argparse
import concurrent.futures
import os
import random
import re
import signal
import subprocess
import sys
import tempfile

import h5py
import numpy as np

# Tiny versions of each scenario, so that a run that is accepted ends fast.
TINY = {
    "shaken_bed": ["system.count=50", "run.t_stop=2", "output.average_after=1", "output.positions=\"all\""],
    "vibrated_bed": ["system.count=200", "run.t_stop=0.5", "output.interval=0.25", "output.average_after=0.25",
                     "output.positions=\"all\""],
    "srd_viscosity": ["system.cells=[8,8]", "run.steps=300", "viscosity.warmup_steps=100"],
    "srd_poiseuille": ["system.cells=[8,8]", "run.steps=300", "poiseuille.warmup_steps=100"],
    "gsrd_cooling": ["system.cells=[8,8,8]", "run.steps=300"],
    "gsrd_shaken": ["system.cells=[8,8,12]", "run.steps=300", "shaken.warmup_steps=100", "output.every_steps=50"],
}
NUMBERS = ["'abc'", "0", "-1", "nan", "inf", "-inf", "1e308", "5e-324", "1e6"]
ARRAYS = ["'abc'", "[]", "[0,0,0]", "[-1,-1,-1]", "[nan,1,1]", "[1e308,1e308,1e308]", "[5e-324,5e-324,5e-324]",
          "[1,2,3,4,5,6,7,8,9,10]", "[inf,1]"]
WALLS = ["[{}]", "[1,2]", "[{axis='q'}]", "[{position=-1}]", "[{axis='z',position=1e308}]",
         "[{axis='z',amplitude=1e308,frequency=1e308}]", "[{axis='z',stiffness=nan}]",
         "[{axis='y',side='upper'}]", "[{axis='x'},{axis='x',side='upper'},{axis='x'}]"]
OTHER = ["'bogus'", "1", "[]", "nan"]
LIBRARY = re.compile(r"bad_alloc|map::at|vector::|basic_string|std::|terminate called|Assertion")


def random_number(rng):
    """Any magnitude a double has, either sign, sometimes an integer."""
    if rng.random() < 0.3:
        return str(rng.choice([-1, 1]) * rng.randrange(0, 10 ** rng.randrange(1, 19)))
    return f"{rng.choice([-1, 1]) * 10 ** rng.uniform(-320, 308):.6g}"


def random_values(rng, default):
    if default.startswith("["):
        return ["[" + ",".join(random_number(rng) for _ in range(rng.randrange(0, 8))) + "]" for _ in range(2)]
    return [random_number(rng) for _ in range(3)]


def keys_of(granflow, scenario, rng):
    out = subprocess.run([granflow, "keys", scenario], capture_output=True, text=True, check=True).stdout
    keys = []
    for line in out.splitlines():
        m = re.match(r"^(\S+)\s+= (.*?)\s+# ", line)
        if not m or m.group(1) in ("scenario", "run.seed") or m.group(1).startswith("output.checkpoint"):
            continue
        key, default = m.group(1), m.group(2)
        if key == "walls":
            values = WALLS
        elif default.startswith("["):
            values = ARRAYS
        elif re.match(r"^-?[0-9.]", default):
            values = NUMBERS
        else:
            values = OTHER
        if values is not WALLS and values is not OTHER:
            values = values + random_values(rng, default)
        keys += [(scenario, key, v) for v in values]
    return keys


def oracle(path):
    """Why the finished result at `path` is not sane, or None."""
    with h5py.File(path, "r") as f:
        bad = []
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset) and name.startswith(("observables", "fields")) and obj.dtype.kind == "f":
                if not np.isfinite(obj[()]).all():
                    bad.append(name)
        f.visititems(visit)
        if bad:
            return f"exit 0 with values that are not finite: {bad[:3]}"
        if "particles/all/position/value" in f and "particles/all/box/edges" in f:
            edges = f["particles/all/box/edges"]
            edges = np.asarray(edges["value"][-1] if isinstance(edges, h5py.Group) else edges[()], dtype=float)
            if edges.ndim == 2:  # a box matrix
                edges = np.diag(edges)
            x = f["particles/all/position/value"][()]
            low, high = -0.25 * edges - 1.0, 1.25 * edges + 1.0
            if not (np.isfinite(x).all() and (x >= low).all() and (x <= high).all()):
                return "exit 0 with particles far outside the box"
    return None


def checkpoint_oracle(path):
    """Why the checkpoint of a run stopped at the time limit is not a live state, or None."""
    if not os.path.exists(path):
        return "exit 130 without a checkpoint"
    with h5py.File(path, "r") as f:
        bad = []
        f.visititems(lambda name, obj: bad.append(name) if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f"
                     and not np.isfinite(obj[()]).all() else None)
    return f"stopped at the time limit with a state that is not finite: {bad[:3]}" if bad else None


def attempt(granflow, scenarios, case, limit, scratch):
    scenario, key, value = case
    out = os.path.join(scratch, f"{scenario}-{abs(hash((key, value)))}.h5md")
    args = [granflow, "run", os.path.join(scenarios, scenario + ".toml"), "-q", "-o", out]
    for setting in TINY[scenario]:
        if not setting.startswith(key + "="):
            args += ["--set", setting]
    args += ["--set", f"{key}={value}"]
    # A run still going at the limit is asked to stop (SIGINT): a live one,
    # however long, checkpoints a finite state and exits 130 at once; one
    # that ignores the signal, or saved a state that is not finite, hangs.
    process = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        _, stderr = process.communicate(timeout=limit)
    except subprocess.TimeoutExpired:
        process.send_signal(signal.SIGINT)
        try:
            _, stderr = process.communicate(timeout=10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.communicate()
            return case, "hang", f"still running after {limit} s and 10 s more after SIGINT"
    status, why = process.returncode, None
    if status == 130:
        why = checkpoint_oracle(out + ".checkpoint")
    elif status not in (0, 2, 3):
        why = f"exit {status}: {stderr.strip()[-300:]}"
    elif LIBRARY.search(stderr):
        why = f"a library's message: {stderr.strip()[-300:]}"
    elif status == 0:
        why = oracle(out)
    for leftover in (out, out + ".checkpoint"):
        if os.path.exists(leftover):
            os.remove(leftover)
    return case, status, why


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("granflow")
    parser.add_argument("scenarios")
    parser.add_argument("--sample", type=int, default=0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--limit", type=float, default=60.0)
    parser.add_argument("--jobs", type=int, default=2)
    a = parser.parse_args()
    rng = random.Random(a.seed)
    cases = [c for scenario in TINY for c in keys_of(a.granflow, scenario, rng)]
    if a.sample:
        cases = random.Random(a.seed).sample(cases, min(a.sample, len(cases)))
    counts, failures = {}, []
    with tempfile.TemporaryDirectory() as scratch, concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        for case, status, why in pool.map(lambda c: attempt(a.granflow, a.scenarios, c, a.limit, scratch), cases):
            tally = counts.setdefault(case[0], {})
            tally[status] = tally.get(status, 0) + 1
            if why:
                failures.append(f"{case[0]} --set {case[1]}={case[2]}: {why}")
    for scenario, tally in counts.items():
        print(f"{scenario}: " + ", ".join(f"exit {s}: {n}" for s, n in sorted(tally.items(), key=str)))
    for failure in failures:
        print("FAIL:", failure)
    print(f"{len(cases)} runs, {len(failures)} failure(s)")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
