#!/usr/bin/env bash
# A damaged or crafted checkpoint ends in a refusal (exit 2, a message that
# says what is wrong and that the checkpoint can be deleted) or in the same
# result as the intact checkpoint; never a crash, a hang or a silently
# different result. The checkpoint is a finished haff_cooling run's final
# state, resumed to a later stop time: truncated at several lengths, random
# bytes overwritten, and values crafted with a recomputed checksum (a mass of
# -1, a negative kinetic energy, a NaN event time, a repeated particle id, a
# position outside the box, a cell index, a partner index, arrays of the
# wrong length, a series whose times are shorter than its steps).
set -u
granflow="$1"
scenario="$2"
source "$(dirname "$0")/common.sh"
args=(--set system.count=300 --set run.t_stop=0.5 --set initial.equilibration_collisions=2 -q)
"$granflow" run "$scenario" "${args[@]}" --set output.final_checkpoint=true -o "$work/base.h5" || exit 1
cp "$work/base.h5.checkpoint" "$work/pristine.checkpoint"
resume() {  # resume CHECKPOINT OUTPUT: 0 done, 2 refused, other: a failure of the test
  cp "$1" "$2.checkpoint"
  timeout 60 "$granflow" run "$scenario" "${args[@]}" --set run.t_stop=1 --resume -o "$2" 2> "$2.log"
}
resume "$work/pristine.checkpoint" "$work/reference.h5" || { echo "FAIL: intact checkpoint does not resume"; exit 1; }
/usr/bin/python3 - "$work" "$granflow" "$scenario" "${args[@]}" <<'PY'
import os, random, shutil, struct, subprocess, sys
import h5py, numpy as np
work, granflow, scenario, args = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
pristine = f"{work}/pristine.checkpoint"
reference = h5py.File(f"{work}/reference.h5", "r")
failures = 0

def resume(path, label, must_resume=False):
    """0: refused or identical; 1: a failure of the program (or a refusal where must_resume)."""
    out = f"{work}/case.h5"
    for leftover in (out, out + ".checkpoint", out + ".partial"):
        if os.path.exists(leftover): os.remove(leftover)
    shutil.copy(path, out + ".checkpoint")
    try:
        run = subprocess.run([granflow, "run", scenario, *args, "--set", "run.t_stop=1", "--resume", "-o", out],
                             capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        print(f"FAIL: {label}: resume hung"); return 1
    if run.returncode == 2 and must_resume:
        print(f"FAIL: {label}: refused: {run.stderr.strip()[-300:]}"); return 1
    if run.returncode == 2:
        if "delete it" not in run.stderr and "checkpoint" not in run.stderr:
            print(f"FAIL: {label}: refused without saying why: {run.stderr.strip()}"); return 1
        print(f"ok: {label}: refused: {run.stderr.strip().splitlines()[-1][:160]}")
        return 0
    if run.returncode != 0:
        print(f"FAIL: {label}: exit {run.returncode}: {run.stderr.strip()[-300:]}"); return 1
    result = h5py.File(out, "r")
    for name in ("kinetic_energy", "collisions_per_particle"):
        if not np.array_equal(result[f"/observables/{name}/value"][()], reference[f"/observables/{name}/value"][()]):
            print(f"FAIL: {label}: resumed without complaint to a different result"); return 1
    print(f"ok: {label}: identical result")
    return 0

# Truncated files.
size = os.path.getsize(pristine)
for fraction in (0.0, 0.1, 0.5, 0.9, 0.999):
    path = f"{work}/truncated.checkpoint"
    with open(pristine, "rb") as f, open(path, "wb") as g: g.write(f.read(int(size * fraction)))
    failures += resume(path, f"truncated to {fraction:.3f}")
# Random bytes anywhere.
rng = random.Random(7)
data = open(pristine, "rb").read()
for trial in range(60):
    damaged = bytearray(data)
    for _ in range(rng.choice((1, 4, 32))):
        damaged[rng.randrange(len(damaged))] = rng.randrange(256)
    path = f"{work}/random.checkpoint"
    open(path, "wb").write(bytes(damaged))
    failures += resume(path, f"random bytes, trial {trial}")

# The seal of engine/io/file_seal.cpp: FNV-1a over the 8-byte words after the
# 512-byte user block, then the remaining bytes, written into the block.
def reseal(path):
    data = open(path, "rb").read()
    body = data[512:]
    words = np.frombuffer(body[: len(body) // 8 * 8], dtype="<u8")
    h = 14695981039346656037
    for word in words.tolist(): h = ((h ^ word) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    for byte in body[len(body) // 8 * 8:]: h = ((h ^ byte) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    line = f"granflow-seal fnv1a64-words {h:016x} {len(body)}\n".encode()
    with open(path, "r+b") as f: f.write(line + b"\0" * (512 - len(line)))

# The seal is checked before HDF5 reads anything: a file edited without it is refused.
shutil.copy(pristine, f"{work}/edited.checkpoint")
with h5py.File(f"{work}/edited.checkpoint", "a") as f: f["/checkpoint"].attrs["note"] = "edited"
failures += resume(f"{work}/edited.checkpoint", "edited without resealing")
resealed = f"{work}/resealed.checkpoint"
shutil.copy(f"{work}/edited.checkpoint", resealed)
reseal(resealed)
failures += resume(resealed, "edited and resealed (the seal is recomputed correctly)", must_resume=True)

# Crafted values with a valid checksum (the FNV-1a of engine/io/checkpoint_file.cpp) and seal.
def checksum(configuration, state):
    h = 14695981039346656037
    def mix(b):
        nonlocal h
        for byte in b: h = ((h ^ byte) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    mix(configuration.encode())
    for name in sorted(state):
        mix(name.encode() + b"\0")
        mix(struct.pack("<Q", len(state[name])))
        mix(np.asarray(state[name], dtype="<f8").tobytes())
    return f"fnv1a64:{h:016x}"

def crafted(label, change, must_resume=False):
    path = f"{work}/crafted.checkpoint"
    shutil.copy(pristine, path)
    with h5py.File(path, "a") as f:
        names = [n.decode() if isinstance(n, bytes) else n for n in f["/checkpoint/names"][()]]
        state = {n: f[f"/checkpoint/values/{k}"][()] for k, n in enumerate(names)}
        change(state)
        del f["/checkpoint/values"], f["/checkpoint/names"]
        names = sorted(state)
        for k, n in enumerate(names):
            f[f"/checkpoint/values/{k}"] = np.asarray(state[n], dtype=float)
        f["/checkpoint/names"] = np.array(names, dtype=h5py.string_dtype())
        toml = f["/parameters/toml"][()]
        f["/checkpoint"].attrs["checksum"] = checksum(toml.decode() if isinstance(toml, bytes) else toml, state)
    reseal(path)
    global failures
    failures += resume(path, label, must_resume)

def setter(name, index, value):
    def change(state):
        state[name] = np.array(state[name], dtype=float)
        state[name][index] = value
    return change

def shorten(name):
    def change(state): state[name] = np.array(state[name])[:-1]
    return change

crafted("unchanged, checksum recomputed", lambda s: None, must_resume=True)
crafted("mass -1", setter("world/mass", 3, -1.0))
crafted("negative kinetic energy", setter("kept/event_driven_gas/scalars", 1, -5.0))
crafted("NaN event time", setter("kept/event_driven_gas/event_time", 2, float("nan")))
crafted("repeated particle id", lambda s: setter("world/particle_id", 1, s["world/particle_id"][0])(s))
crafted("position outside the box", setter("kept/event_driven_gas/hot", 0, 7.5))
crafted("cell index out of range", setter("kept/event_driven_gas/cell", 5, 1e9))
crafted("partner index out of range", setter("kept/event_driven_gas/plan", 1, 1e6))
crafted("event_time shorter than N", shorten("kept/event_driven_gas/event_time"))
crafted("mass column shorter than N", shorten("world/mass"))
crafted("series time shorter than step", shorten("history/kinetic_energy/time"))
crafted("clock missing", lambda s: s.pop("clock"))
print(f"{failures} failure(s)")
sys.exit(1 if failures else 0)
PY
