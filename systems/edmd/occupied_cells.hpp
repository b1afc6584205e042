#pragma once
// Which cells of a neighbourhood hold particles: the first step of every
// prediction. About half the cells around a particle are empty in a fluid
// and most are in a dilute gas, and whether the next one is empty is a coin
// toss the processor cannot predict; reading the heads of eight cells at
// once and walking only the occupied ones replaces a branch per cell by a
// bit scan per occupied cell.

#include <cstdint>

namespace granflow::edmd {

// Offsets are read eight at a time: an offset list is padded to a multiple
// of this with zeros (the origin cell, which is readable; its bits are
// dropped).
inline constexpr int occupancy_group = 8;

// Bit k of the result is set where the cell at origin + offsets[k] (k below
// count, at most 64) has a particle, whose list then starts at heads[k];
// `head` is the grid's array of list heads (negative: empty).
std::uint64_t occupied_cells(const std::int32_t* head, std::uint32_t origin, const std::int32_t* offsets, int count,
                             std::int32_t* heads);

}  // namespace granflow::edmd
