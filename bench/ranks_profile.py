#!/usr/bin/env python3
# What the weak-scaling benchmarks of one system over MPI ranks read from
# the /profile of their result files (run with /usr/bin/python3, for h5py):
#   step FILE NAME...          mean seconds per step of the named step systems
#                              (the calls of the first one found are the steps)
#   report ONES TWOS FILE PART  the medians of the rounds' times (ONES, TWOS:
#                              space-separated seconds per step), the
#                              efficiency t(1 rank) / t(2 ranks), and each
#                              rank's parts `PART.rank<r>.<part>` of FILE's step
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


def report(ones, twos, path, part):
    one = [float(x) for x in ones.split()]
    two = [float(x) for x in twos.split()]
    ratios = [a / b for a, b in zip(one, two)]
    print(f"median 1 rank {statistics.median(one) * 1e3:.2f} ms/step, 2 ranks {statistics.median(two) * 1e3:.2f} ms/step")
    print(f"weak-scaling efficiency: median of the rounds' ratios {statistics.median(ratios):.3f} "
          f"(range {min(ratios):.3f}-{max(ratios):.3f})")
    table = rows(path)
    steps = table[part][0]
    parts = [n.split(".")[-1] for n in table if n.startswith(part + ".rank0.")]
    print("parts of the 2-rank step, ms/step:", " ".join(f"{'rank ' + str(r):>8}" for r in range(2)))
    for p in parts:
        print(f"  {p:<16}", " ".join(f"{table[f'{part}.rank{r}.{p}'][1] / steps * 1e3:8.2f}" for r in range(2)))


if __name__ == "__main__":
    if sys.argv[1] == "step":
        step(sys.argv[2], sys.argv[3:])
    else:
        report(*sys.argv[2:6])
