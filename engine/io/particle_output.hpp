#pragma once
// Writes particle data to /particles/all in particle-id order, whatever order
// the engine keeps them in memory.

#include <cstdint>
#include <numeric>
#include <vector>

#include "components/image_count.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/species.hpp"
#include "components/velocity.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/io/h5md_file.hpp"

namespace granflow {

// Storage index of each particle id (identity where the World keeps no ids).
template <class V>
std::vector<std::uint32_t> storage_order(const V& view) {
  std::vector<std::uint32_t> order(view.size());
  if (!view.template has<ParticleId>()) {
    std::iota(order.begin(), order.end(), 0u);
    return order;
  }
  const auto& id = view.template read<ParticleId>();
  for (std::uint32_t i = 0; i < view.size(); ++i) order[id[i]] = i;
  return order;
}

template <class Column>
std::vector<double> flatten_by_id(const Column& column, const std::vector<std::uint32_t>& order) {
  using T = typename Column::value_type;
  std::vector<double> out;
  if constexpr (std::is_arithmetic_v<T>) {
    out.reserve(order.size());
    for (auto i : order) out.push_back(static_cast<double>(column[i]));
  } else {
    out.reserve(order.size() * static_cast<std::size_t>(T::RowsAtCompileTime));
    for (auto i : order)
      for (int a = 0; a < T::RowsAtCompileTime; ++a) out.push_back(column[i][a]);
  }
  return out;
}

// Integer columns (labels, image counts) in particle-id order.
template <class Column>
std::vector<std::int32_t> flatten_integers_by_id(const Column& column, const std::vector<std::uint32_t>& order) {
  using T = typename Column::value_type;
  std::vector<std::int32_t> out;
  if constexpr (std::is_arithmetic_v<T>) {
    out.reserve(order.size());
    for (auto i : order) out.push_back(static_cast<std::int32_t>(column[i]));
  } else {
    out.reserve(order.size() * static_cast<std::size_t>(T::RowsAtCompileTime));
    for (auto i : order)
      for (int a = 0; a < T::RowsAtCompileTime; ++a) out.push_back(static_cast<std::int32_t>(column[i][a]));
  }
  return out;
}

// Frames are written in id order, so the id of row k is k at every time.
using ParticleConstantsView = View<Reads<Mass, Radius, Species, ParticleId>, Writes<>>;

inline void write_particle_constants(H5mdFile& file, const ParticleConstantsView& view) {
  const auto order = storage_order(view);
  file.write_particle_constant("mass", flatten_by_id(view.read<Mass>(), order), 1, unit::mass);
  if (view.has<Radius>())
    file.write_particle_constant("radius", flatten_by_id(view.read<Radius>(), order), 1, unit::length);
  std::vector<std::int32_t> id(view.size());
  std::iota(id.begin(), id.end(), 0);
  file.write_particle_constant("id", id);
  if (view.has<Species>())
    file.write_particle_constant("species", flatten_integers_by_id(view.read<Species>(), order));
}

// Positions (wrapped into the box), velocities and, where the World counts
// periodic images, the images: position + image * edges is the unwrapped position.
template <int D>
using ParticleFrameView = View<Reads<Position<D>, Velocity<D>, ImageCount<D>, ParticleId>, Writes<>>;

template <int D>
void append_particle_frame(H5mdFile& file, const ParticleFrameView<D>& view, std::int64_t step, double time) {
  const auto order = storage_order(view);
  file.append_particle_frame("position", step, time, flatten_by_id(view.template read<Position<D>>(), order), D);
  file.append_particle_frame("velocity", step, time, flatten_by_id(view.template read<Velocity<D>>(), order), D);
  if (view.template has<ImageCount<D>>())
    file.append_particle_frame("image", step, time,
                               flatten_integers_by_id(view.template read<ImageCount<D>>(), order), D);
}

}  // namespace granflow
