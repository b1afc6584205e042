#pragma once
// Checkpoints of event-driven runs. A checkpoint is an H5MD file holding the
// resolved configuration, the particles in the engine's storage order, the
// engine's event state and every observable written so far; a run resumed
// from it continues the same event sequence and rewrites the same output.

#include <cstdint>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "components/box.hpp"
#include "components/clock.hpp"
#include "components/collision_count.hpp"
#include "components/last_collision_time.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/config.hpp"
#include "engine/h5md_file.hpp"
#include "engine/h5md_reader.hpp"
#include "systems/edmd/event_driven_gas.hpp"
#include "systems/observables/observable_writer.hpp"
#include "systems/observables/particle_snapshot.hpp"

namespace granflow::edmd {

struct CheckpointContents {
  std::string configuration;  // resolved TOML
  std::size_t next_output = 0;
  Clock clock;
  std::map<std::string, double> derived;
  std::map<std::string, std::vector<double>> engine;
  std::map<std::string, std::vector<ObservableWriter::Sample>> observables;
};

namespace detail {
// Storage order, not id order: the engine's state refers to storage indices.
template <class Column>
std::vector<double> column_as_doubles(const Column& column) {
  std::vector<std::uint32_t> identity(column.size());
  std::iota(identity.begin(), identity.end(), 0u);
  return flatten_by_id(column, identity);
}
template <class Column>
void column_from_doubles(Column& column, const std::vector<double>& data) {
  using T = typename Column::value_type;
  if constexpr (std::is_arithmetic_v<T>) {
    if (data.size() != column.size()) throw std::invalid_argument("checkpoint column has the wrong size");
    for (std::size_t i = 0; i < data.size(); ++i) column[i] = static_cast<T>(data[i]);
  } else {
    constexpr int d = T::RowsAtCompileTime;
    if (data.size() != column.size() * d) throw std::invalid_argument("checkpoint column has the wrong size");
    for (std::size_t i = 0; i < column.size(); ++i)
      for (int a = 0; a < d; ++a) column[i][a] = data[i * d + a];
  }
}
}  // namespace detail

template <int D>
void write_checkpoint(const std::string& path, const std::string& scenario, const Config& config, const World& world,
                      const EventDrivenGas<D>& gas, const ObservableWriter& writer, std::size_t next_output,
                      const std::map<std::string, double>& derived) {
  H5mdFile file(path, scenario);
  file.write_parameters(config);
  const auto& box = world.resource<Box<D>>();
  file.write_box(box.edges(), box.h5md_boundary());
  for (const auto& [name, value] : derived) file.write_attribute("/parameters/derived", name, value);
  const std::string particles = "/checkpoint/world";
  file.write_array(particles, "position", detail::column_as_doubles(world.component<Position<D>>()));
  file.write_array(particles, "velocity", detail::column_as_doubles(world.component<Velocity<D>>()));
  file.write_array(particles, "mass", detail::column_as_doubles(world.component<Mass>()));
  file.write_array(particles, "radius", detail::column_as_doubles(world.component<Radius>()));
  file.write_array(particles, "particle_id", detail::column_as_doubles(world.component<ParticleId>()));
  file.write_array(particles, "collision_count", detail::column_as_doubles(world.component<CollisionCount>()));
  if (world.has_component<LastCollisionTime>())
    file.write_array(particles, "last_collision_time", detail::column_as_doubles(world.component<LastCollisionTime>()));
  for (const auto& [name, values] : gas.save_state()) file.write_array("/checkpoint/engine", name, values);
  const auto& clock = world.resource<Clock>();
  file.write_array("/checkpoint", "progress",
                   {static_cast<double>(next_output), clock.time, static_cast<double>(clock.step)});
  for (const auto& [name, samples] : writer.history())
    for (const auto& sample : samples) {
      if (sample.value.size() == 1)
        file.append_observable(name, sample.step, sample.time, sample.value.front());
      else
        file.append_observable(name, sample.step, sample.time, sample.value);
    }
  file.finish();
}

// Fills an empty world from a checkpoint and returns the rest of its contents.
template <int D>
CheckpointContents read_checkpoint(const std::string& path, World& world, const std::vector<std::string>& observables,
                                   const std::vector<std::string>& derived_names) {
  H5mdReader reader(path);
  CheckpointContents out;
  out.configuration = reader.string_dataset("/parameters/toml");
  const std::string particles = "/checkpoint/world";
  const auto mass = reader.doubles(particles + "/mass").values;
  world.resize(mass.size());
  detail::column_from_doubles(world.add_component<Mass>(), mass);
  detail::column_from_doubles(world.add_component<Radius>(), reader.doubles(particles + "/radius").values);
  detail::column_from_doubles(world.add_component<Position<D>>(), reader.doubles(particles + "/position").values);
  detail::column_from_doubles(world.add_component<Velocity<D>>(), reader.doubles(particles + "/velocity").values);
  detail::column_from_doubles(world.add_component<ParticleId>(), reader.doubles(particles + "/particle_id").values);
  detail::column_from_doubles(world.add_component<CollisionCount>(),
                              reader.doubles(particles + "/collision_count").values);
  if (reader.exists(particles + "/last_collision_time"))
    detail::column_from_doubles(world.add_component<LastCollisionTime>(),
                                reader.doubles(particles + "/last_collision_time").values);
  for (const char* name : {"hot", "plan", "cell", "event_time", "scalars", "collapse"})
    out.engine[name] = reader.doubles(std::string("/checkpoint/engine/") + name).values;
  const auto progress = reader.doubles("/checkpoint/progress").values;
  out.next_output = static_cast<std::size_t>(progress.at(0));
  out.clock.time = progress.at(1);
  out.clock.step = static_cast<std::int64_t>(progress.at(2));
  for (const auto& name : derived_names) out.derived[name] = reader.double_attribute("/parameters/derived", name);
  for (const auto& name : observables) {
    const std::string group = "/observables/" + name;
    if (!reader.exists(group)) continue;
    const auto steps = reader.integers(group + "/step");
    const auto times = reader.doubles(group + "/time").values;
    const auto values = reader.doubles(group + "/value");
    const std::size_t width = steps.empty() ? 1 : values.values.size() / steps.size();
    for (std::size_t k = 0; k < steps.size(); ++k)
      out.observables[name].push_back(
          {steps[k], times[k], {values.values.begin() + static_cast<std::ptrdiff_t>(k * width),
                                values.values.begin() + static_cast<std::ptrdiff_t>((k + 1) * width)}});
  }
  return out;
}

}  // namespace granflow::edmd
