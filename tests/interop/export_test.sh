#!/usr/bin/env bash
# granflow export: the extended XYZ and XDMF of a 3D periodic run
# (haff_cooling) and of a 2D reflecting run with two species (crater_impact)
# read back, by a parser of each format written from its specification, to
# the positions, velocities, radii, species, boxes and times of the result
# file; a file without frames is refused with a message that says why.
set -u
granflow="$1"
scenarios="$2"
source "$(dirname "$0")/../cli/common.sh"
"$granflow" run "$scenarios/haff_cooling.toml" --set output.positions=all --set run.t_stop=1 -q -o "$work/haff.h5md" || exit 1
"$granflow" run "$scenarios/crater_impact.toml" --set system.count=500 --set run.t_stop=0.02 -q -o "$work/crater.h5md" || exit 1
for name in haff crater; do
  "$granflow" export "$work/$name.h5md" --format xyz || failures=$((failures + 1))
  mkdir -p "$work/elsewhere"
  "$granflow" export "$work/$name.h5md" --format xdmf -o "$work/elsewhere/$name.xdmf" || failures=$((failures + 1))
done
/usr/bin/python3 - "$work" <<'PY' || failures=$((failures + 1))
import os, re, shlex, sys, xml.etree.ElementTree as ET
import h5py, numpy as np
work = sys.argv[1]
bad = []
def check(ok, what):
    print(("ok: " if ok else "FAIL: ") + what)
    if not ok: bad.append(what)

def read_extended_xyz(path):
    """Frames as dicts: the comment line's key=value pairs and one array per Properties column."""
    frames, lines = [], open(path).read().splitlines()
    k = 0
    while k < len(lines):
        n = int(lines[k]); info = dict(item.split("=", 1) for item in shlex.split(lines[k + 1]))
        fields = info["Properties"].split(":")
        rows = [line.split() for line in lines[k + 2 : k + 2 + n]]
        columns, c = {}, 0
        for name, kind, width in zip(fields[0::3], fields[1::3], fields[2::3]):
            width = int(width)
            cast = {"R": float, "I": int, "S": str, "L": str}[kind]
            columns[name] = np.array([[cast(r[c + j]) for j in range(width)] for r in rows]).squeeze()
            c += width
        frames.append((info, columns)); k += 2 + n
    return frames

for name, d in (("haff", 3), ("crater", 2)):
    f = h5py.File(f"{work}/{name}.h5md", "r"); p = f["/particles/all"]
    positions, times = p["position/value"][()], p["position/time"][()]
    frames = read_extended_xyz(f"{work}/{name}.xyz")
    check(len(frames) == len(times), f"{name}.xyz has {len(frames)} frames of {len(times)}")
    edges = p["box/edges/value"][()] if isinstance(p["box/edges"], h5py.Group) else None
    boundary = [b.decode() for b in p["box"].attrs["boundary"]]
    worst = 0.0
    for k, (info, columns) in enumerate(frames):
        worst = max(worst, np.abs(columns["pos"][:, :d] - positions[k]).max(),
                    np.abs(columns["velo"][:, :d] - p["velocity/value"][k]).max())
        if abs(float(info["Time"]) - times[k]) > 1e-12: check(False, f"{name}.xyz frame {k} time")
        lattice = np.array(info["Lattice"].split(), dtype=float).reshape(3, 3)
        box = np.diag(edges[k]) if edges is not None else p["box/edges"][()]
        if not np.allclose(np.diag(lattice)[:d], box): check(False, f"{name}.xyz frame {k} lattice {lattice}")
    check(worst < 1e-9 * max(1.0, np.abs(p["velocity/value"][()]).max()), f"{name}.xyz positions and velocities to {worst:.2g}")
    check(np.allclose(frames[0][1]["radius"], p["radius"][()], rtol=1e-9), f"{name}.xyz radii")
    species = p["species"][()] if "species" in p else np.zeros(len(p["radius"]), dtype=int)
    check(list(frames[0][1]["species"]) == [f"S{s}" for s in species], f"{name}.xyz species")
    pbc = frames[0][0]["pbc"].split()[:d]
    check(pbc == ["T" if b == "periodic" else "F" for b in boundary], f"{name}.xyz pbc {pbc} for {boundary}")

    # XDMF: every DataItem resolves in the HDF5 file, hyperslabs select the frame's rows.
    path = f"{work}/elsewhere/{name}.xdmf"
    root = ET.parse(path).getroot()
    def resolve(item):
        if item.get("ItemType") == "HyperSlab":
            spec, source = item.findall("DataItem")
            start, stride, count = np.array(spec.text.split(), dtype=int).reshape(3, -1)
            data = resolve(source)
            index = tuple(slice(s, s + c * t, t) for s, c, t in zip(start, count, stride))
            return data[index].reshape([int(x) for x in item.get("Dimensions").split()])
        file, dataset = item.text.strip().split(":")
        with h5py.File(os.path.join(os.path.dirname(path), file), "r") as g:
            data = g[dataset][()]
        check_shape = [int(x) for x in item.get("Dimensions").split()]
        assert list(data.shape) == check_shape, (dataset, data.shape, check_shape)
        return data
    grids = root.findall("./Domain/Grid/Grid")
    check(len(grids) == len(times), f"{name}.xdmf has {len(grids)} grids of {len(times)}")
    ok = True
    for k, grid in enumerate(grids):
        ok &= float(grid.find("Time").get("Value")) == times[k]
        geometry = grid.find("Geometry")
        ok &= geometry.get("GeometryType") == ("XYZ" if d == 3 else "XY")
        ok &= np.array_equal(resolve(geometry.find("DataItem")), positions[k])
        attributes = {a.get("Name"): resolve(a.find("DataItem")) for a in grid.findall("Attribute")}
        ok &= np.array_equal(attributes["velocity"], p["velocity/value"][k])
        ok &= np.array_equal(attributes["radius"], p["radius"][()])
    check(ok, f"{name}.xdmf geometry, velocity, radius and times of every frame read back")
    check("species" not in p or np.array_equal(attributes["species"], p["species"][()]), f"{name}.xdmf species")
sys.exit(1 if bad else 0)
PY
# SRD fields: the XDMF written beside the result file describes /fields on
# the cell grid; every attribute resolves to the field's frame.
"$granflow" run "$scenarios/gsrd_cooling.toml" --set 'system.cells=[8,8,8]' --set run.steps=40 \
  --set fields.every_steps=20 --set fields.window=5 -q -o "$work/gsrd.h5md" || exit 1
/usr/bin/python3 - "$work" <<'PY' || failures=$((failures + 1))
import os, sys, xml.etree.ElementTree as ET
import h5py, numpy as np
work = sys.argv[1]
f = h5py.File(f"{work}/gsrd.h5md", "r")
root = ET.parse(f"{work}/gsrd.fields.xdmf").getroot()
grids = root.findall("./Domain/Grid/Grid")
assert len(grids) == 2, f"{len(grids)} field frames, expected 2 (steps 20 and 40)"
for k, grid in enumerate(grids):
    assert grid.find("Topology").get("TopologyType") == "3DCoRectMesh"
    assert grid.find("Topology").get("Dimensions") == "9 9 9"
    assert float(grid.find("Time").get("Value")) == f["/fields/density/time"][k]
    for attribute in grid.findall("Attribute"):
        slab = attribute.find("DataItem")
        spec, source = slab.findall("DataItem")
        start, stride, count = np.array(spec.text.split(), dtype=int).reshape(3, -1)
        file, dataset = source.text.strip().split(":")
        data = h5py.File(os.path.join(work, file), "r")[dataset][()]
        selected = data[tuple(slice(s, s + c * t, t) for s, c, t in zip(start, count, stride))]
        name = attribute.get("Name")
        assert np.array_equal(selected.reshape(data.shape[1:]), f[f"/fields/{name}/value"][k]), name
# Every particle is in one cell of every sample: the density field sums to N.
density = f["/fields/density/value"][()]
n = 8 ** 3 * int(f["/parameters/srd"].attrs["particles_per_cell"])
assert np.allclose(density.sum(axis=(1, 2, 3)), n), density.sum(axis=(1, 2, 3))
print("ok: SRD fields and their XDMF read back (2 frames, density sums to N)")
PY

# A file without particle frames is refused, naming what to change.
"$granflow" run "$scenarios/haff_cooling.toml" --set output.positions=none --set run.t_stop=0.1 -q -o "$work/none.h5md" || exit 1
output=$("$granflow" export "$work/none.h5md" --format xyz 2>&1); status=$?
[[ $status -eq 2 && "$output" == *"output.positions"* ]] && echo "ok: no frames refused" \
  || { echo "FAIL: export of a file without frames: exit $status: $output"; failures=$((failures + 1)); }
[[ $failures -eq 0 ]] && echo "all export checks passed"
exit $((failures > 0))
