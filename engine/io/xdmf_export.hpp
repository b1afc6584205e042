#pragma once
// XDMF descriptions of a result file's particle frames and grid fields, for
// ParaView ("Xdmf3 Reader" and the legacy "XDMF Reader") and VisIt.
//
// ParaView's Xdmf3 readers read neither a hyperslab of a [frames, ...]
// dataset nor a two-component vector. So every array of every frame is an
// HDF5 virtual dataset in a small companion file, OUT.xdmf.h5 beside OUT.xdmf,
// that maps onto its slice of the result file without copying it; vectors of
// 2D runs are padded with a zero third component (the plane z = 0). The
// companion names the result file by a path relative to itself: keep the
// three files together, or move them together.

#include <cstddef>
#include <string>
#include <vector>

namespace granflow {

// Particle frames (/particles/all) and fields (/fields) of a finished
// result file. Returns the number of frames written; throws InputError where
// the file has neither.
std::size_t export_xdmf(const std::string& result, const std::string& output);

// One field on the unshifted cell grid: /fields/NAME/value of shape
// [frames, cells z, y, x(, components)].
struct GridField {
  std::string name;
  std::size_t components = 1;
};

// The fields a run is writing, described for the name its result file will
// have (it need not exist yet): cells along x, y(, z), each frame's time.
void write_field_xdmf(const std::string& result, const std::string& output, const std::vector<std::size_t>& cells,
                      const std::vector<double>& times, const std::vector<GridField>& fields);

}  // namespace granflow
