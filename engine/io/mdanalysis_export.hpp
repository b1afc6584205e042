#pragma once
// An H5MD file shaped the way MDAnalysis's H5MD reader (2.4) expects, over a
// result file's particle frames, without copying them.
//
// That reader takes the particle count from a particle group called
// `trajectory`, refuses unit strings it does not know (reduced units among
// them) on positions, velocities and times even when asked not to convert,
// and attaches to frame k the k-th row of every series in /observables. A
// result file keeps its frames in /particles/all with reduced units, and its
// series are sampled at every output (the SDE's time averages at lags), so
// where the frames are fewer than the outputs (output.positions = final or
// first_last) row k is not frame k's. The exported file's
// /particles/trajectory maps position and velocity onto the result's (HDF5
// virtual datasets, which name the result by a path relative to the export:
// keep the two files together), with steps, times and box but no units; its
// /observables hold, of every series sampled at each frame's step, the rows
// of those steps only; a series missing at some frame is left out and named
// in the log.

#include <cstddef>
#include <string>

namespace granflow {

// Returns the number of frames; throws InputError where the file has no
// particle frames or is not 3D (MDAnalysis reads 3D boxes only).
std::size_t export_mdanalysis(const std::string& result, const std::string& output);

}  // namespace granflow
