#!/usr/bin/env python3
# What the benchmarks of one system over MPI ranks read from the /profile of
# their result files and print (run with /usr/bin/python3, for h5py):
#   step FILE NAME...        mean seconds per step of the named step systems
#                            (the calls of the first one found are the steps)
#   compare A TIMES_A B TIMES_B WHAT
#                            the medians of two programs' times per step, run
#                            by turns (TIMES_*: space-separated seconds), and
#                            WHAT: the median (and range) of the rounds'
#                            ratios time A / time B
#   parts FILE STEP          each rank's parts `STEP.rank<r>.<part>` of FILE's
#                            step, in ms per step
import statistics
import sys

import h5py


def rows(path):
    f = h5py.File(path, "r")
    names = [n.decode() if isinstance(n, bytes) else n for n in f["profile/system"][()]]
    return dict(zip(names, zip(f["profile/calls"][()], f["profile/total_seconds"][()])))


def step(path, names):
    table = rows(path)
    present = [n for n in names if n in table]
    steps = table[present[0]][0]
    print(sum(table[n][1] for n in present) / steps)


def compare(name_a, times_a, name_b, times_b, what):
    a = [float(x) for x in times_a.split()]
    b = [float(x) for x in times_b.split()]
    ratios = [x / y for x, y in zip(a, b)]
    print(f"median {name_a} {statistics.median(a) * 1e3:.2f} ms/step, {name_b} {statistics.median(b) * 1e3:.2f} ms/step")
    print(f"{what}: median of the rounds' ratios {statistics.median(ratios):.3f} "
          f"(range {min(ratios):.3f}-{max(ratios):.3f})")


def parts(path, step_name):
    table = rows(path)
    steps = table[step_name][0]
    ranks = sorted({int(n.split(".")[1][4:]) for n in table if n.startswith(step_name + ".rank")})
    names = [n.split(".")[-1] for n in table if n.startswith(step_name + ".rank0.")]
    print("parts of the step over ranks, ms/step:", " ".join(f"{'rank ' + str(r):>8}" for r in ranks))
    for p in names:
        print(f"  {p:<16}", " ".join(f"{table[f'{step_name}.rank{r}.{p}'][1] / steps * 1e3:8.2f}" for r in ranks))


if __name__ == "__main__":
    command, arguments = sys.argv[1], sys.argv[2:]
    if command == "step":
        step(arguments[0], arguments[1:])
    elif command == "compare":
        compare(*arguments[:5])
    else:
        parts(*arguments[:2])
