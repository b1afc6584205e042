// A new scenario outside granflow: the Sonine coefficient a2 of the velocity
// distribution of a freely cooling granular gas. A system of our own
// (SonineObserver) is wired with granflow's event-driven step, kinetic
// energy observer and H5MD writer; Schedule orders them from what each reads
// and writes. Compare a2 with the first Sonine approximation of kinetic
// theory (van Noije & Ernst 1998; Brilliantov & Poeschel 2006):
//   a2 = 16 (1 - xi)(1 - 2 xi^2) / (9 + 24 d - xi (41 - 8 d) + 30 xi^2 (1 - xi)).

#include <fmt/format.h>

#include <cmath>
#include <string>
#include <vector>

#include "components/clock.hpp"
#include "components/velocity.hpp"
#include "engine/config.hpp"
#include "engine/h5md_file.hpp"
#include "engine/observable_store.hpp"
#include "engine/profiler.hpp"
#include "engine/run_control.hpp"
#include "engine/schedule.hpp"
#include "engine/system.hpp"
#include "systems/edmd/event_driven_step.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/observables/kinetic_energy.hpp"
#include "systems/observables/observable_writer.hpp"

using namespace granflow;

constexpr int D = 3;

// a2 = d / (d + 2) <v^4> / <v^2>^2 - 1: zero for a Maxwell-Boltzmann gas.
class SonineObserver : public System {
 public:
  std::string name() const override { return "observe_sonine_a2"; }
  Access access() const override { return {{Velocity<D>::key}, {ObservableStore::access_key("sonine_a2")}}; }
  void run(World& world) override {
    double v2 = 0.0, v4 = 0.0;
    for (const auto& v : world.component<Velocity<D>>().values) {
      const double s = v.squaredNorm();
      v2 += s;
      v4 += s * s;
    }
    const double n = static_cast<double>(world.size());
    world.resource<ObservableStore>().set("sonine_a2", D / (D + 2.0) * (v4 / n) / ((v2 / n) * (v2 / n)) - 1.0);
  }
};

double sonine_theory(double xi, double d) {
  return 16 * (1 - xi) * (1 - 2 * xi * xi) / (9 + 24 * d - xi * (41 - 8 * d) + 30 * xi * xi * (1 - xi));
}

int main(int argc, char** argv) {
  ConfigSchema schema;
  schema.choice("scenario", "sonine_cooling", {"sonine_cooling"}, "scenario name");
  edmd::declare_gas_keys(schema, {});
  Config config(schema);
  config.set("system.count", std::int64_t{2000});
  try {
    for (int k = 1; k + 1 < argc; k += 2)
      if (std::string(argv[k]) == "--set") config.apply_override(argv[k + 1]);
  } catch (const ConfigError& error) {
    fmt::print(stderr, "error: {}\n", error.what());
    return 2;
  }

  World world;
  edmd::build_gas<D>(world, config);
  edmd::EventDrivenGas<D> gas(world, edmd::collision_parameters_from(config));
  gas.start(0.0);
  world.emplace_resource<Clock>();
  auto& control = world.emplace_resource<RunControl>();
  auto& store = world.emplace_resource<ObservableStore>();
  const std::vector<std::string> observables{"kinetic_energy", "temperature", "sonine_a2"};
  for (const auto& name : observables) store.declare(name);

  H5mdFile file("sonine.h5", "sonine_cooling");
  file.write_parameters(config);
  Profiler profiler;
  Schedule schedule(profiler);
  schedule.emplace<edmd::EventDrivenStep<D>>(gas, edmd::AdvanceLimits{});
  schedule.emplace<KineticEnergyObserver<D>>();
  schedule.emplace<SonineObserver>();
  schedule.emplace<ObservableWriter>(file, observables);

  // a2 settles within a few collisions per particle; average the rest.
  const double t_stop = config.real("run.t_stop");
  double sum = 0.0;
  int samples = 0;
  for (int k = 1; k <= 200 && !control.stop; ++k) {
    control.target_time = t_stop * k / 200.0;
    schedule.run(world);
    if (k > 50) {
      sum += store.slot("sonine_a2").value.at(0);
      ++samples;
    }
  }
  file.write_profile(profiler.entries());
  file.finish();
  const double xi = config.real("collision.restitution");
  fmt::print("xi = {}: a2 = {:.4f} (mean of {} outputs), first Sonine approximation {:.4f}\n", xi, sum / samples,
             samples, sonine_theory(xi, D));
  fmt::print("{}", profiler.table());
  return 0;
}
