#pragma once
// Particle frames of a result file as a GSD file in the HOOMD schema (what
// gsd.hoomd, HOOMD-blue, OVITO, freud and MDAnalysis read). Per frame:
// configuration/step, dimensions and box, particles/N, position, velocity and
// image, and log/time (the frame's time); in the first frame the particle
// types (species k is type "k"), typeid, mass and diameter, which later
// frames inherit as the schema provides. HOOMD's box is centred on the
// origin, so positions are shifted by half the box (x - L/2); images keep
// their meaning (unwrapped = position + image L). 2D runs are written as
// HOOMD writes them: dimensions 2, Lz = 0, z = 0. Single precision, as HOOMD
// stores positions.

#include <cstddef>
#include <string>

namespace granflow {

// Returns the number of frames written. Throws InputError where the file has
// no particle frames or cannot be read or written.
std::size_t export_gsd(const std::string& result, const std::string& output);

}  // namespace granflow
