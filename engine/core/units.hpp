#pragma once
// Units of what granflow writes, in H5MD's unit-string notation (space-
// separated symbols with integer powers). Every method works in reduced
// units: L is the unit in which the configuration gives lengths (box edges,
// radii), M the unit of its masses and T the unit of its times; energies and
// temperatures (k_B = 1) are in M L2 T-2. docs/units.md says what L, M and T
// are for each method and scenario.

namespace granflow::unit {

inline constexpr const char* length = "L";
inline constexpr const char* area = "L2";  // lengths squared: MSD
inline constexpr const char* mass = "M";
inline constexpr const char* time = "T";
inline constexpr const char* velocity = "L T-1";
inline constexpr const char* acceleration = "L T-2";
inline constexpr const char* energy = "M L2 T-2";
inline constexpr const char* force = "M L T-2";
inline constexpr const char* diffusivity = "L2 T-1";
inline constexpr const char* rate = "T-1";
inline constexpr const char* per_velocity = "T L-1";  // a speed distribution's density
inline constexpr const char* angle = "rad";
inline constexpr const char* none = "1";  // counts, ratios, labels

}  // namespace granflow::unit
