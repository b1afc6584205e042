"""Two directories of result files (run_scenarios.sh, two builds) hold the
same results: every dataset and attribute of every file bit for bit, except
what says when, where and how fast a file was written (/provenance,
/profile, /h5md, the file's seal).

With --allow-added, entries only AFTER holds (a dataset a change adds
beside the unchanged ones) are listed but do not fail the comparison; an
entry that changed or went missing always does.

  compare.py [--allow-added] BEFORE_DIR AFTER_DIR"""
import os
import sys

import h5py
import numpy as np

SKIPPED = ("provenance", "profile", "h5md")


def contents(path):
    out = {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if name.split("/")[0] in SKIPPED:
                return
            if isinstance(obj, h5py.Dataset):
                out[name] = obj[()]
            for key, value in obj.attrs.items():
                out[f"{name}@{key}"] = value
        f.visititems(visit)
        for key, value in f.attrs.items():
            if "seal" not in key:
                out[f"@{key}"] = value
    return out


def same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.dtype.kind != b.dtype.kind:
        return False
    if a.dtype.kind == "f":
        return np.array_equal(a, b, equal_nan=True)
    return np.array_equal(a, b)


arguments = [a for a in sys.argv[1:] if a != "--allow-added"]
allow_added = len(arguments) < len(sys.argv) - 1
before, after = arguments[:2]
names = sorted(n for n in os.listdir(before) if n.endswith(".h5md"))
failures = 0
for name in names:
    if not os.path.exists(os.path.join(after, name)):
        print(f"FAIL: {name}: missing after")
        failures += 1
        continue
    a, b = contents(os.path.join(before, name)), contents(os.path.join(after, name))
    added = sorted(k for k in b if k not in a) if allow_added else []
    differ = [k for k in sorted(set(a) | set(b)) if k not in added and (k not in a or k not in b or not same(a[k], b[k]))]
    if differ:
        failures += 1
        print(f"FAIL: {name}: {len(differ)} of {len(a)} entries differ, e.g. {differ[:5]}")
    else:
        print(f"ok: {name}: {len(a)} datasets and attributes identical" +
              (f"; {len(added)} added: {added[:5]}" if added else ""))
print(f"{len(names)} files, {failures} differ")
sys.exit(1 if failures or not names else 0)
