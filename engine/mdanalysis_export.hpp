#pragma once
// An H5MD file shaped the way MDAnalysis's H5MD reader (2.4) expects, over a
// result file's particle frames, without copying them.
//
// That reader takes the particle count from a particle group called
// `trajectory`, and attaches to frame k the k-th row of every series in
// /observables. A result file keeps its frames in /particles/all, and its
// series are sampled at every output (and the SDE's time averages at lags),
// so where the frames are fewer than the outputs (output.positions = final
// or first_last) row k is not frame k's. The exported file links
// /particles/trajectory to the result's /particles/all (an HDF5 external
// link, by a path relative to itself: keep the two files together), and
// holds, of every series sampled at each frame's step, the rows of those
// steps only; a series missing at some frame is left out and named in the log.

#include <cstddef>
#include <string>

namespace granflow {

// Returns the number of frames; throws InputError where the file has no
// particle frames or is not 3D (MDAnalysis reads 3D boxes only).
std::size_t export_mdanalysis(const std::string& result, const std::string& output);

}  // namespace granflow
