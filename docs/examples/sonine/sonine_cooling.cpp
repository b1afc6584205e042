// A scenario of your own, outside granflow: the Sonine coefficient a2 of the
// velocity distribution of a freely cooling granular gas. It adds one
// observer (SonineObserver) to granflow's event-driven gas and kinetic
// energy observer, registers itself, and gets granflow's whole command line
// (run, sweep, keys, list, info, --resume, --profile) beside the built-in
// scenarios. Compare a2 with the first Sonine approximation of kinetic
// theory (van Noije & Ernst 1998; Brilliantov & Poeschel 2004):
//   a2 = 16 (1 - xi)(1 - 2 xi^2) / (9 + 24 d - xi (41 - 8 d) + 30 xi^2 (1 - xi)).

#include <fmt/format.h>

#include <memory>

#include "components/velocity.hpp"
#include "engine/app/cli.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/run/run.hpp"
#include "engine/run/scenario.hpp"
#include "systems/edmd/event_driven_run.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/observables/kinetic_energy.hpp"

using namespace granflow;

constexpr int D = 3;

// a2 = d / (d + 2) <v^4> / <v^2>^2 - 1: zero for a Maxwell-Boltzmann gas.
// Its view lists what it reads; reading anything else would not compile.
class SonineObserver : public SystemOf<Reads<Velocity<D>>, Writes<>> {
 public:
  std::string name() const override { return "observe_sonine_a2"; }
  Access access() const override { return View::access().writes_observable("sonine_a2", unit::none); }
  void run_on(View view) override {
    double v2 = 0.0, v4 = 0.0;
    for (const auto& v : view.read<Velocity<D>>().values) {
      const double s = v.squaredNorm();
      v2 += s;
      v4 += s * s;
    }
    const double n = static_cast<double>(view.size());
    view.observables().set("sonine_a2", D / (D + 2.0) * (v4 / n) / ((v2 / n) * (v2 / n)) - 1.0);
  }
};

double sonine_theory(double xi, double d) {
  return 16 * (1 - xi) * (1 - 2 * xi * xi) / (9 + 24 * d - xi * (41 - 8 * d) + 30 * xi * xi * (1 - xi));
}

void build(Run& run) {
  const Config& c = run.config();
  run.initial_state([&](World& world) {
    edmd::build_gas<D>(world, c, run.seed());
    run.derive("initial_kinetic_energy", total_kinetic_energy<D>(world));
  });
  const double energy0 = run.derived("initial_kinetic_energy");
  edmd::add_event_driven_gas<D>(run, edmd::box_from<D>(c), edmd::CollisionParameters::from(c),
                                edmd::advance_limits_from(c, run.world().size(), energy0), energy0);
  const double t_stop = c.real("run.t_stop");
  const auto outputs = std::make_shared<EveryTime>(t_stop / 200, t_stop);
  run.observe<KineticEnergyObserver<D>>(outputs);
  run.observe<SonineObserver>(outputs);
  run.stop_at_time(t_stop);
  // a2 settles within a few collisions per particle; average the last three quarters.
  run.at_finish([&run](H5mdFile& file, const RunOutcome&) {
    const auto& series = run.recorder().history().at("sonine_a2");
    double sum = 0.0;
    std::size_t samples = 0;
    for (std::size_t k = series.size() / 4; k < series.size(); ++k, ++samples) sum += series[k].value.at(0);
    const double xi = run.config().real("collision.restitution");
    file.write_attribute("/observables", "sonine_a2_mean", sum / static_cast<double>(samples));
    fmt::print("xi = {}: a2 = {:.4f} (mean of {} outputs), first Sonine approximation {:.4f}\n", xi,
               sum / static_cast<double>(samples), samples, sonine_theory(xi, D));
  });
}

GRANFLOW_REGISTER_SCENARIO(sonine_cooling, Scenario{
  .name = "sonine_cooling",
  .summary = "Sonine coefficient a2 of a freely cooling gas against kinetic theory (example)",
  .default_output = "sonine.h5md",
  .keys = [](ConfigSchema& s) {
    edmd::GasDefaults gas;
    gas.count = 2000;
    edmd::declare_gas_keys(s, gas);
  },
  .build = build,
})

int main(int argc, char** argv) { return granflow::main(argc, argv); }
