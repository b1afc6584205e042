"""The source folders are layers, and includes run one way: down. A file may
include from its own folder and from folders of lower layers only; an
include that runs up a layer, or between two folders of one layer, fails
here with the file, the line and both layers.

Layers, lowest first (docs/composing-scenarios.md):
  engine                 World, columns, access, schedule, RNG, configuration,
                         units, H5MD and checkpoints, Run and Runner, the CLI
  components             the particle columns and resources
  systems/initial        placement and initial velocities
  systems/edmd           the event-driven gas (and the preparations it runs)
  systems/sde, systems/observables
  systems/srd, systems/dem
  cuda                   the CUDA back end's programs
  scenarios

One exception remains, named here so that no other can appear: engine/ still
holds layers both below components (the core that components include) and
above them (the Run, the particle schema of the result file, the CLI);
ENGINE_ABOVE_COMPONENTS lists the engine files that include components. None
of the core files that components include may include one of those.

  layers_test.py SOURCE_DIR"""
import os
import re
import sys

LAYERS = [
    ["engine"],
    ["components"],
    ["systems/initial"],
    ["systems/edmd"],
    ["systems/sde", "systems/observables"],
    ["systems/srd", "systems/dem"],
    ["cuda"],
    ["scenarios"],
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
engine_above = set()
for path in files:
    if path.startswith("engine/") and any(t.startswith("components/") for _, t in includes(path)):
        engine_above.add(path)
for path in files:
    source = folder_of(path)
    for number, target in includes(path):
        destination = folder_of(target)
        if destination is None or destination == source:
            continue
        if source == "engine" and destination == "components":
            continue  # the exception above; checked below
        if RANK[destination] >= RANK[source]:
            failures.append(f"{path}:{number} includes {target}: {source} (layer {RANK[source]}) may not include "
                            f"{destination} (layer {RANK[destination]})")
# What components include from engine/ is the core: it must not reach the engine files above components.
core = set()
pending = [t for p in files if p.startswith("components/") for _, t in includes(p) if t.startswith("engine/")]
while pending:
    path = pending.pop()
    if path in core:
        continue
    core.add(path)
    pending.extend(t for _, t in includes(path) if t.startswith("engine/"))
for path in sorted(core & engine_above):
    failures.append(f"{path} is in the core components build on, yet includes components/")

print(f"{len(files)} files in {len(RANK)} folders; {len(core)} core engine headers; {len(engine_above)} engine files "
      f"above components (to move out of the core folder)")
for failure in failures:
    print("FAIL:", failure)
print("ok: every include runs down a layer" if not failures else f"{len(failures)} includes run up a layer")
sys.exit(1 if failures else 0)
