#pragma once
// Particle frames of a result file as extended XYZ, in the conventions ASE
// (ase.io.read) and OVITO read: per frame the box (Lattice), periodic axes
// (pbc), Time and Step; per particle a chemical symbol standing for its
// species (ASE builds atoms from symbols: species k is the element of atomic
// number k + 1) and the species index itself (typeid), position (pos),
// velocity (velo), momenta and masses (ASE's names, so that get_masses() and
// get_velocities() return the run's), radius, periodic image and id. 2D runs
// lie in the plane z = 0 of a box whose third vector is a unit normal.

#include <cstddef>
#include <string>

namespace granflow {

// Returns the number of frames written. Throws InputError where the file has
// no particle frames or cannot be read.
std::size_t export_extended_xyz(const std::string& result, const std::string& output);

}  // namespace granflow
