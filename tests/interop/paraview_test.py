"""XDMF exports in ParaView (pvpython, offscreen): the "Xdmf3 Reader"
docs/reading-results.md names (Xdmf3ReaderS; also Xdmf3ReaderT and the
legacy XDMFReader) opens the particle frames of every file (2D and 3D) and
the SRD fields with every array; each time step's points, velocities, radii
and images, and each field's density (which sums to the particle count), are
compared with the result file. One frame is rendered offscreen as spheres
(Point Gaussian, radius array) and saved as a PNG, which must show particles.
Skips (77) where ParaView's Python is not installed.

  xvfb-run -a pvpython paraview_test.py DIR [SCREENSHOT.png]"""
import sys

try:
    from paraview import servermanager
    from paraview.simple import (XDMFReader, Xdmf3ReaderS, Xdmf3ReaderT, ColorBy, GetActiveViewOrCreate, Show,
                                 Render, SaveScreenshot, ResetSession)
    from paraview.vtk.util.numpy_support import vtk_to_numpy
except ImportError:
    print("skipped: ParaView's Python is not installed (apt-get install paraview)")
    sys.exit(77)
import os

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from truth import FIELD_FILES, PARTICLE_FILES, Checks, Frames  # noqa: E402

directory = os.path.abspath(sys.argv[1])
screenshot = sys.argv[2] if len(sys.argv) > 2 else os.path.join(directory, "paraview_haff.png")
check = Checks("ParaView " + servermanager.vtkSMProxyManager.GetParaViewSourceVersion())
READERS = {"Xdmf3ReaderS": lambda path: Xdmf3ReaderS(FileName=path),
           "Xdmf3ReaderT": lambda path: Xdmf3ReaderT(FileName=path),
           "XDMFReader": lambda path: XDMFReader(FileNames=[path])}


def blocks(data):
    """The datasets in what a reader produced (multiblocks and multipieces nest them)."""
    if data is None:
        return
    if data.IsA("vtkMultiBlockDataSet"):
        for b in range(data.GetNumberOfBlocks()):
            yield from blocks(data.GetBlock(b))
    elif data.IsA("vtkMultiPieceDataSet"):
        for b in range(data.GetNumberOfPieces()):
            yield from blocks(data.GetPiece(b))
    else:
        yield data


def grid_with(reader, array, kind):
    """The dataset holding the named point ("points") or cell ("cells") array."""
    for data in blocks(servermanager.Fetch(reader)):
        arrays = data.GetPointData() if kind == "points" else data.GetCellData()
        if arrays.GetArray(array) is not None:
            return data
    return None


def point_array(dataset, name):
    return vtk_to_numpy(dataset.GetPointData().GetArray(name))


for name, dimension in PARTICLE_FILES:
    truth = Frames(f"{directory}/{name}.h5md")
    for reader_name, make in READERS.items():
        reader = make(f"{directory}/{name}.xdmf")
        # A file with fields too has their times as well (SRD).
        times = list(reader.TimestepValues)
        ok = all(np.isclose(times, t).any() for t in truth.times)
        worst = 0.0
        arrays = set()
        for k, t in enumerate(truth.times):
            reader.UpdatePipeline(t)
            data = grid_with(reader, "velocity", "points")
            if data is None:
                ok = False
                break
            points = vtk_to_numpy(data.GetPoints().GetData())
            arrays = {data.GetPointData().GetArrayName(a) for a in range(data.GetPointData().GetNumberOfArrays())}
            if points.shape != (truth.count, 3) or data.GetNumberOfCells() != truth.count:
                ok = False
                break
            scale = max(1.0, np.abs(truth.velocities[k]).max())
            worst = max(worst, np.abs(points - truth.padded(truth.positions[k])).max(),
                        np.abs(point_array(data, "velocity") - truth.padded(truth.velocities[k])).max() / scale)
            if truth.radius is not None:
                worst = max(worst, np.abs(point_array(data, "radius") - truth.radius).max())
            if truth.images is not None and not np.array_equal(point_array(data, "image"), truth.padded(truth.images[k])):
                ok = False
        expected = {"velocity", "mass", "id"} | ({"image"} if truth.images is not None else set()) \
            | ({"radius"} if truth.radius is not None else set()) \
            | ({"species"} if "species" in h5py.File(f"{directory}/{name}.h5md", "r")["/particles/all"] else set())
        check(ok and worst < 1e-12 and expected <= arrays,
              f"{name}.xdmf with {reader_name}: {truth.frames} time steps of {truth.count} points and cells, "
              f"arrays {sorted(arrays)}, within {worst:.2g} of the file")
        ResetSession()

for name, dimension in FIELD_FILES:
    with h5py.File(f"{directory}/{name}.h5md", "r") as f:
        density = f["/fields/density/value"][()]
        velocity = f["/fields/velocity/value"][()]
        times = f["/fields/density/time"][()]
        particles = int(f["/parameters/srd"].attrs["particles_per_cell"]) * np.prod(density.shape[1:])
    cells = np.prod(density.shape[1:])
    for reader_name, make in READERS.items():
        reader = make(f"{directory}/{name}.fields.xdmf")
        ok = np.allclose(list(reader.TimestepValues), times)
        for k, t in enumerate(times):
            reader.UpdatePipeline(t)
            data = grid_with(reader, "density", "cells")
            if data is None:
                ok = False
                break
            cell_data = data.GetCellData()
            got = {cell_data.GetArrayName(a) for a in range(cell_data.GetNumberOfArrays())}
            if data.GetNumberOfCells() != cells or got != {"density", "velocity", "temperature"}:
                ok = False
                break
            rho = vtk_to_numpy(cell_data.GetArray("density"))
            v = vtk_to_numpy(cell_data.GetArray("velocity"))
            ok &= np.allclose(rho, density[k].ravel()) and abs(rho.sum() - particles) < 1e-6 * particles
            ok &= v.shape == (cells, 3) and np.allclose(v[:, :dimension], velocity[k].reshape(cells, dimension))
        check(ok, f"{name}.fields.xdmf with {reader_name}: {len(times)} frames of {cells} cells with density, "
                  f"velocity (3 components) and temperature; density sums to N = {particles}")
        ResetSession()

# An offscreen render of the last frame of the gas, as spheres.
reader = Xdmf3ReaderS(FileName=f"{directory}/haff.xdmf")
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [480, 480]
view.ViewTime = reader.TimestepValues[-1]
display = Show(reader, view)
display.SetRepresentationType("Point Gaussian")
display.ShaderPreset = "Sphere"
display.ScaleByArray = 1
display.SetScaleArray = ["POINTS", "radius"]
display.UseScaleFunction = 0  # the radius array as it is, not mapped onto [0, 1]
display.GaussianRadius = 1.0
ColorBy(display, ("POINTS", "velocity", "Magnitude"))
display.RescaleTransferFunctionToDataRange(True)
view.ResetCamera()
Render(view)
SaveScreenshot(screenshot, view, ImageResolution=[480, 480])
try:
    from PIL import Image
    pixels = np.asarray(Image.open(screenshot).convert("L"), dtype=float)
    varied = pixels.std() > 5
except ImportError:
    from paraview.vtk.vtkIOImage import vtkPNGReader
    png = vtkPNGReader()
    png.SetFileName(screenshot)
    png.Update()
    pixels = vtk_to_numpy(png.GetOutput().GetPointData().GetScalars()).astype(float)
    varied = pixels.std() > 5
check(os.path.getsize(screenshot) > 1000 and varied, f"offscreen render of haff.xdmf saved as {screenshot}")
check.close(skip_teardown=True)
