#pragma once
// A seal on every file granflow writes: HDF5 data starts after a 512-byte
// user block, whose first line holds a hash of everything after it. It is
// checked with plain reads before HDF5 opens a file, because HDF5 itself can
// crash on damaged files (a corrupted heap of variable-length strings sends
// its reader out of bounds). A checkpoint whose seal does not match is
// refused; `granflow info` refuses a broken seal unless told the file was
// edited on purpose.

#include <cstdint>
#include <string>

namespace granflow {

inline constexpr std::uint64_t seal_block_bytes = 512;  // the HDF5 user block

// Writes the seal into the user block of a closed file.
void seal_file(const std::string& path);

enum class SealState { matches, absent, broken };
SealState check_seal(const std::string& path);
// "intact", "has no granflow seal", "was changed or damaged after it was written".
std::string describe(SealState state);

}  // namespace granflow
