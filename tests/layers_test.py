"""The source folders are layers, and includes run one way: down. A file may
include from its own folder and from folders of lower layers only; an
include that runs up a layer, or between two folders of one layer, fails
here with the file, the line and both layers. So no two folders include
each other, and every folder of the tree below is in a layer (a source
folder the list does not name fails too).

Layers, lowest first (docs/composing-scenarios.md):
  engine/core            World, columns, access, schedule, RNG, configuration,
                         units, triggers
  components             the particle columns and resources
  engine/io              H5MD, checkpoints, the particle schema, exports
  engine/run             Run, Runner, scenarios as the engine knows them
  systems/geometry       the cell grid and the counting sort the methods share
  systems/initial        placement and initial velocities
  systems/edmd           the event-driven gas (and the preparations it runs)
  systems/sde, systems/observables
  systems/srd, systems/dem
  cuda                   the CUDA back end's programs
  scenarios
  engine/app             the CLI and the sweeps

  layers_test.py SOURCE_DIR"""
import os
import re
import sys

LAYERS = [
    ["engine/core"],
    ["components"],
    ["engine/io"],
    ["engine/run"],
    ["systems/geometry"],
    ["systems/initial"],
    ["systems/edmd"],
    ["systems/sde", "systems/observables"],
    ["systems/srd", "systems/dem"],
    ["cuda"],
    ["scenarios"],
    ["engine/app"],
]
RANK = {folder: rank for rank, folders in enumerate(LAYERS) for folder in folders}
SOURCES = (".hpp", ".cpp", ".cu", ".cuh")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')

root = sys.argv[1]


def folder_of(path):
    folder = os.path.dirname(path)
    return folder if folder in RANK else None


def includes(path):
    with open(os.path.join(root, path), errors="replace") as f:
        for number, line in enumerate(f, 1):
            m = INCLUDE.match(line)
            if m and os.path.exists(os.path.join(root, m.group(1))):
                yield number, m.group(1)


files = []
for folder in RANK:
    for name in sorted(os.listdir(os.path.join(root, folder))):
        if name.endswith(SOURCES):
            files.append(f"{folder}/{name}")

failures = []
for top in ["engine", "components", "systems", "cuda", "scenarios"]:
    for path, _, names in os.walk(os.path.join(root, top)):
        folder = os.path.relpath(path, root)
        if any(n.endswith(SOURCES) for n in names) and folder not in RANK:
            failures.append(f"{folder} holds sources but is in no layer")
for path in files:
    source = folder_of(path)
    for number, target in includes(path):
        destination = folder_of(target)
        if destination is None or destination == source:
            continue
        if RANK[destination] >= RANK[source]:
            failures.append(f"{path}:{number} includes {target}: {source} (layer {RANK[source]}) may not include "
                            f"{destination} (layer {RANK[destination]})")

print(f"{len(files)} files in {len(RANK)} folders of {len(LAYERS)} layers")
for failure in failures:
    print("FAIL:", failure)
print("ok: every include runs down a layer" if not failures else f"{len(failures)} failures")
sys.exit(1 if failures else 0)
