#pragma once
// Time-averaged MSD of the first `tracked` particles (by particle id) from
// unwrapped positions, sampled whenever its trigger fires and correlated on
// the fly (systems/observables/multiple_tau_msd.hpp). At the end of the run
// it writes three observables, each one vector over lags:
//   time_averaged_msd_lag   lag in sampling intervals
//   time_averaged_msd       particle average of the time-averaged MSD
//   ergodicity_breaking     EB = <(delta^2)^2> / <delta^2>^2 - 1 over particles
// msd.* keys belong to this family (declare_msd_keys).

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/core/config.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/trigger.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/run/run.hpp"
#include "engine/run/run_control.hpp"
#include "systems/observables/msd.hpp"
#include "systems/observables/multiple_tau_msd.hpp"

namespace granflow {

inline const SystemDescription observe_time_averaged_msd_description{"observe_time_averaged_msd", "time-averaged MSD and ergodicity breaking, multiple-tau correlator"};

struct MsdDefaults {
  std::int64_t time_average_particles = 0;
  double sample_interval = 0.0;  // 0: no msd.sample_interval key (sampled every step)
};

// Units of the MSD series an ensemble's reduction writes (ensemble MSD with
// its error and theory, the diffusivity, the time average over lags).
inline void declare_msd_series_units(H5mdFile& file) {
  for (const char* name : {"msd", "msd_stderr", "msd_theory", "time_averaged_msd", "time_averaged_msd_stderr"})
    file.declare_unit(name, unit::area);
  for (const char* name : {"diffusivity", "diffusivity_theory"}) file.declare_unit(name, unit::diffusivity);
  file.declare_unit("ergodicity_breaking", unit::none);
}

inline void declare_msd_keys(ConfigSchema& schema, const MsdDefaults& d) {
  schema.integer("msd.time_average_particles", d.time_average_particles, 0, 100000000,
                 "particles of each run whose time-averaged MSD is accumulated (0: none)");
  if (d.sample_interval > 0)
    schema.real("msd.sample_interval", d.sample_interval, 0.0, std::numeric_limits<double>::infinity(),
                "time between the samples of the time-averaged MSD", true);
  schema.integer("msd.correlator_points", 16, 4, 1024, "lags per level of the multiple-tau correlator");
}

// Samples when its trigger fires; publishes the result in the Runner's final
// round (RunControl::ending). Add it with add_time_averaged_msd().
template <int D>
using TimeAveragedMsdBase = SystemOf<Reads<Position<D>, ImageCount<D>, ParticleId, Box<D>, RunControl>, Writes<>>;

template <int D>
class TimeAveragedMsdObserver : public TimeAveragedMsdBase<D>, public Stateful {
 public:
  using View = typename TimeAveragedMsdBase<D>::View;
  // `samples`: how many samples the run will take at most (sets the longest lag).
  TimeAveragedMsdObserver(std::size_t tracked, std::uint64_t samples, int points)
      : tracked_(tracked), correlator_(tracked, D, samples, points), buffer_(tracked * D) {}

  std::string name() const override { return "observe_time_averaged_msd"; }
  Access access() const override {
    return View::access()
        .writes_observable("time_averaged_msd_lag", unit::time)
        .writes_observable("time_averaged_msd", unit::area)
        .writes_observable("ergodicity_breaking", unit::none);
  }
  void run_on(View view) override {
    if (view.template read<RunControl>().ending) {
      const auto result = correlator_.result();
      auto& store = view.observables();
      store.set("time_averaged_msd_lag", result.lag);
      store.set("time_averaged_msd", result.msd);
      store.set("ergodicity_breaking", result.ergodicity_breaking);
      return;
    }
    // Particles are tracked by id; storage order changes when an engine re-sorts.
    const UnwrappedPositions<D> unwrapped(view);
    for (std::size_t i = 0; i < view.size(); ++i)
      if (const std::uint32_t id = unwrapped.id(i); id < tracked_) {
        const Vec<D> u = unwrapped(i);
        for (int a = 0; a < D; ++a) buffer_[id * D + a] = u[a];
      }
    correlator_.add(buffer_.data());
  }

  StateMap save_state() const override { return correlator_.save_state(); }
  void restore_state(const StateMap& state) override { correlator_.restore_state(state); }

 private:
  std::size_t tracked_;
  MultipleTauMsd correlator_;
  std::vector<double> buffer_;
};

// The observer from the msd.* keys, sampling whenever `sampling` fires, up to `samples` samples.
template <int D>
void add_time_averaged_msd(Run& run, const TriggerPtr& sampling, std::uint64_t samples) {
  const Config& config = run.config();
  const auto tracked = std::min<std::size_t>(run.world().size(),
                                             static_cast<std::size_t>(config.integer("msd.time_average_particles")));
  if (tracked == 0) return;
  auto& observer = run.observe<TimeAveragedMsdObserver<D>>(
      std::make_shared<AnyOf>(std::vector<TriggerPtr>{sampling, std::make_shared<AtEnd>()}), tracked, samples,
      static_cast<int>(config.integer("msd.correlator_points")));
  run.keep("time_averaged_msd", observer);
}

}  // namespace granflow
