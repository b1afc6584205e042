#pragma once
// Writes particle data to /particles/all in particle-id order, whatever order
// the engine keeps them in memory.

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "components/image_count.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/species.hpp"
#include "components/velocity.hpp"
#include "engine/core/observed_part.hpp"
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

// The same constants where each rank holds its own particles, which carry
// their ids (observers that run by rank): every rank sends its particles'
// ids and constants to the writing rank, which places them by id, so that
// no rank holds more of the whole than its constants. `file` is the writing
// rank's (null on the others, which take part all the same). Collective.
inline void write_particle_constants_by_rank(H5mdFile* file, const ParticleConstantsView& view,
                                             const ObservedPart& part) {
  const bool radius = view.has<Radius>(), species = view.has<Species>();
  const std::size_t width = 2 + (radius ? 1 : 0) + (species ? 1 : 0);
  const auto& id = view.read<ParticleId>();
  const auto& mass = view.read<Mass>();
  std::vector<double> mine;
  mine.reserve(view.size() * width);
  for (std::size_t i = 0; i < view.size(); ++i) {
    mine.push_back(static_cast<double>(id[i]));
    mine.push_back(mass[i]);
    if (radius) mine.push_back(view.read<Radius>()[i]);
    if (species) mine.push_back(static_cast<double>(view.read<Species>()[i]));
  }
  const std::vector<double> all = part.to_writer(mine);
  if (!file) return;
  const std::size_t n = all.size() / width;
  std::vector<double> masses(n), radii(radius ? n : 0);
  std::vector<std::int32_t> ids(n), kinds(species ? n : 0);
  std::vector<bool> seen(n, false);
  for (std::size_t k = 0; k < n; ++k) {
    const double* row = all.data() + k * width;
    const auto i = static_cast<std::size_t>(row[0]);
    if (i >= n || seen[i])
      throw std::logic_error(fmt::format("particle constants: id {} of {} particles arrived twice or out of range", i, n));
    seen[i] = true;
    masses[i] = row[1];
    if (radius) radii[i] = row[2];
    if (species) kinds[i] = static_cast<std::int32_t>(row[width - 1]);
  }
  file->write_particle_constant("mass", masses, 1, unit::mass);
  if (radius) file->write_particle_constant("radius", radii, 1, unit::length);
  std::iota(ids.begin(), ids.end(), 0);
  file->write_particle_constant("id", ids);
  if (species) file->write_particle_constant("species", kinds);
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

// The same frame where each rank holds its own particles (observers that
// run by rank): the ranks send their particles to the writing rank in
// blocks of frame_block ids, which it writes as rows of the frame, so that
// no rank holds more than one block of the whole. `file` is the writing
// rank's (null on the others, which take part all the same).
inline constexpr std::size_t frame_block = std::size_t{1} << 18;

template <int D>
void append_particle_frame_by_rank(H5mdFile* file, const ParticleFrameView<D>& view, const ObservedPart& part,
                                   std::int64_t step, double time) {
  const std::size_t n = view.size();
  const auto total = static_cast<std::size_t>(part.total(static_cast<double>(n)));
  const auto& id = view.template read<ParticleId>();
  std::vector<std::uint32_t> by_id(n);
  std::iota(by_id.begin(), by_id.end(), 0u);
  std::sort(by_id.begin(), by_id.end(), [&](std::uint32_t a, std::uint32_t b) { return id[a] < id[b]; });
  const auto element = [&](const char* name, bool integers, auto&& values_of) {
    if (file) file->begin_particle_frame(name, step, time, total, D, integers);
    std::size_t next = 0;
    for (std::size_t first = 0; first < total; first += frame_block) {
      const std::size_t rows = std::min(frame_block, total - first);
      std::vector<double> mine;
      for (; next < n && id[by_id[next]] < first + rows; ++next) {
        mine.push_back(static_cast<double>(id[by_id[next]]));
        for (int a = 0; a < D; ++a) mine.push_back(values_of(by_id[next], a));
      }
      const std::vector<double> block = part.to_writer(mine);
      if (!file) continue;
      if (block.size() != rows * (D + 1))
        throw std::logic_error(fmt::format("particle frame: {} of ids {}..{} arrived", block.size() / (D + 1), first,
                                           first + rows - 1));
      std::vector<double> row_values(rows * D);
      for (std::size_t k = 0; k < block.size(); k += D + 1) {
        const auto row = static_cast<std::size_t>(block[k]) - first;
        std::copy_n(block.begin() + static_cast<std::ptrdiff_t>(k + 1), D,
                    row_values.begin() + static_cast<std::ptrdiff_t>(row * D));
      }
      if (integers) {
        const std::vector<std::int32_t> as_integers(row_values.begin(), row_values.end());
        file->write_particle_rows(name, first, rows, as_integers.data());
      } else {
        file->write_particle_rows(name, first, rows, row_values.data());
      }
    }
  };
  const auto& x = view.template read<Position<D>>();
  const auto& v = view.template read<Velocity<D>>();
  element("position", false, [&](std::uint32_t i, int a) { return x[i][a]; });
  element("velocity", false, [&](std::uint32_t i, int a) { return v[i][a]; });
  if (view.template has<ImageCount<D>>()) {
    const auto& image = view.template read<ImageCount<D>>();
    element("image", true, [&](std::uint32_t i, int a) { return static_cast<double>(image[i][a]); });
  }
}

}  // namespace granflow
