#pragma once
// The GSD file layer (the format of HOOMD-blue and the gsd package), as both
// the exporter writes it and initial.from reads it: a 256-byte header, the
// data chunks, the list of chunk names (64-byte segments in version 1,
// 0-terminated in version 2) and an index of 32-byte entries sorted by frame,
// then name.

#include <cstddef>
#include <cstdint>

namespace granflow {

inline constexpr std::uint64_t gsd_magic = 0x65DF65DF65DF65DFull;

constexpr std::uint32_t gsd_version(std::uint32_t major, std::uint32_t minor) { return major << 16 | minor; }

enum class GsdType : std::uint8_t {
  uint8 = 1, uint16, uint32, uint64, int8, int16, int32, int64, float32, float64
};

// Bytes per element; 0 for a type the format does not define.
constexpr std::size_t gsd_type_size(std::uint8_t type) {
  constexpr std::size_t sizes[] = {0, 1, 2, 4, 8, 1, 2, 4, 8, 4, 8};
  return type < sizeof sizes / sizeof sizes[0] ? sizes[type] : 0;
}

#pragma pack(push, 1)
struct GsdHeader {
  std::uint64_t magic = gsd_magic;
  std::uint64_t index_location = 0;
  std::uint64_t index_allocated_entries = 0;
  std::uint64_t namelist_location = 0;
  std::uint64_t namelist_allocated_entries = 0;  // in 64-byte segments
  std::uint32_t schema_version = 0;
  std::uint32_t gsd_version = 0;
  char application[64] = {};
  char schema[64] = {};
  char reserved[80] = {};
};
struct GsdIndexEntry {
  std::uint64_t frame;
  std::uint64_t rows;
  std::int64_t location;
  std::uint32_t columns;
  std::uint16_t name;
  std::uint8_t type;
  std::uint8_t flags;
};
#pragma pack(pop)
static_assert(sizeof(GsdHeader) == 256 && sizeof(GsdIndexEntry) == 32);

}  // namespace granflow
