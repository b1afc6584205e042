#pragma once
// The speeds of every particle, per species, whenever its trigger fires
// (snapshots many collisions per particle apart are nearly independent
// samples of the speed distribution), kept across checkpoints.

#include <string>

#include "components/species.hpp"
#include "components/velocity.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "systems/observables/speed_samples.hpp"

namespace granflow {

inline const SystemDescription observe_speed_snapshot_description{
    "observe_speed_snapshot", "the speeds of every particle, per species, for the speed histograms"};

// Writes itself: whatever reads the samples at the end is ordered after it.
template <int D>
class SpeedSnapshotObserver : public SystemOf<Reads<Velocity<D>, Species>, Writes<SpeedSnapshotObserver<D>>>,
                              public Stateful {
 public:
  using View = typename SystemOf<Reads<Velocity<D>, Species>, Writes<SpeedSnapshotObserver<D>>>::View;
  explicit SpeedSnapshotObserver(std::size_t species) : samples_(species) {}
  std::string name() const override { return "observe_speed_snapshot"; }
  void run_on(View view) override {
    samples_.add(view.template read<Velocity<D>>(),
                 view.template has<Species>() ? &view.template read<Species>() : nullptr);
    ++taken_;
  }
  static constexpr const char* key = "speed_snapshots";
  const SpeedSamples& samples() const { return samples_; }
  std::size_t taken() const { return taken_; }
  StateMap save_state() const override {
    StateMap out{{"taken", {static_cast<double>(taken_)}}};
    for (std::size_t s = 0; s < samples_.species_count(); ++s) out[std::to_string(s)] = samples_.speeds(s);
    return out;
  }
  void restore_state(const StateMap& state) override {
    taken_ = static_cast<std::size_t>(state.at("taken").at(0));
    for (std::size_t s = 0; s < samples_.species_count(); ++s) samples_.set_speeds(s, state.at(std::to_string(s)));
  }

 private:
  SpeedSamples samples_;
  std::size_t taken_ = 0;
};

}  // namespace granflow
