#pragma once
// Every random stream in granflow has its id here, so no two uses of the same
// seed can ever draw correlated numbers.

#include <cstdint>

namespace granflow::stream {

inline constexpr std::uint32_t placement = 1;        // random particle positions
inline constexpr std::uint32_t initial_velocity = 2; // initial velocity directions / Maxwell draws
inline constexpr std::uint32_t ensemble_seed = 3;    // seeds derived for ensemble members
inline constexpr std::uint32_t lattice_vacancy = 4;  // which lattice sites stay empty in a melted lattice
inline constexpr std::uint32_t melt_velocity = 5;    // velocities of the elastic run that melts a lattice
inline constexpr std::uint32_t sde_noise = 6;        // Wiener increments of SDE stepping, keyed by step and particle
inline constexpr std::uint32_t sde_initial = 7;      // initial velocities of SDE ensembles
inline constexpr std::uint32_t run_seed = 8;         // seeds of the independent runs inside one scenario
inline constexpr std::uint32_t srd_grid_shift = 9;   // the SRD grid's random shift, keyed by step
inline constexpr std::uint32_t srd_rotation = 10;    // each SRD cell's rotation (sign or axis), keyed by step and cell
inline constexpr std::uint32_t srd_initial = 11;     // initial positions and velocities of SRD particles
inline constexpr std::uint32_t srd_ghosts = 12;      // the ghost particles of SRD cells cut by a wall, keyed by step and cell
inline constexpr std::uint32_t dem_initial = 13;     // initial velocities of DEM spheres
inline constexpr std::uint32_t compression_velocity = 14;  // velocities of the elastic runs between compression steps

}  // namespace granflow::stream
