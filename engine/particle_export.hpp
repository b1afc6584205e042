#pragma once
// Particle frames of a result file for visualisation tools: extended XYZ
// (OVITO, ASE and most particle viewers read it) and XDMF, an XML
// description of the result file's own datasets that ParaView and VisIt
// read in place, one grid of points per frame in a temporal collection.
// Both take the frames under /particles/all: position (needed), velocity,
// radius, species and id where present, the box of each frame.

#include <string>

namespace granflow {

// Returns the number of frames written. Throws InputError where the file has
// no particle frames or cannot be read.
std::size_t export_extended_xyz(const std::string& result, const std::string& output);
std::size_t export_xdmf(const std::string& result, const std::string& output);

}  // namespace granflow
