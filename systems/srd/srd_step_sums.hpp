#pragma once
// Sums over the particles for observers that sample every step (profiles,
// shear stress), computed where the particles live when the SRD step runs on
// a device (srd.device = "cuda" or "thrust_host"), so that the state is not
// copied back every step. The device step puts this resource into the World.
// A sampler asks for its sums the first time it runs (from the host state,
// copied back that once); from the next step on the device step fills them
// at the end of every step, and the sampler reads them instead of the
// particles. Without a device step there is no such resource and samplers
// read the particles, as always.

#include <cstdint>
#include <vector>

#include "components/clock.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"

namespace granflow::srd {

struct LayerSumsRequest {
  int axis = 0;
  int flow = 0;
  int layers = 1;
  bool operator==(const LayerSumsRequest&) const = default;
};

template <int D>
struct SrdStepSums {
  static constexpr const char* key = "srd_step_sums";

  // What samplers asked for.
  std::vector<LayerSumsRequest> layer_requests;
  bool stress_requested = false;

  // The step the sums are of (-1: none yet).
  std::int64_t step = -1;
  // Per request, layers x (3 + D): particles, sum of v[flow], of |v|^2 and of each v_a.
  std::vector<std::vector<double>> layers;
  // Sums of vx vy, vy (y - L_y / 2) and vy^2 (per unit mass), and of the
  // cells' collisional transfer.
  double stress[3] = {0, 0, 0};
  double transfer = 0.0;

  // The index of a layer request, registered if new.
  std::size_t ask(const LayerSumsRequest& request) {
    for (std::size_t k = 0; k < layer_requests.size(); ++k)
      if (layer_requests[k] == request) return k;
    layer_requests.push_back(request);
    return layer_requests.size() - 1;
  }
  bool current(std::int64_t clock_step) const { return step == clock_step; }
  bool has_layers(std::size_t index, std::int64_t clock_step) const {
    return current(clock_step) && index < layers.size();
  }
};

// A sampler's layer sums from the device step: asked for the first time it
// samples (where there is a device step), read from the next step on.
template <int D>
class StepSumsRequest {
 public:
  // Registers `request` (and, with `stress`, the stress sums) where the
  // World has a device step; nothing otherwise.
  void ask(View<Reads<>, Writes<SrdStepSums<D>>> view, const LayerSumsRequest& request, bool stress = false) {
    if (asked_ || !view.template has<SrdStepSums<D>>()) return;
    auto& sums = view.template write<SrdStepSums<D>>();
    index_ = sums.ask(request);
    if (stress) sums.stress_requested = true;
    asked_ = true;
  }
  // The device step's sums of this step, or null where they are not there.
  const SrdStepSums<D>* ready(const View<Reads<SrdStepSums<D>, Clock>, Writes<>>& view) const {
    if (!asked_ || !view.template has<SrdStepSums<D>>()) return nullptr;
    const auto& sums = view.template read<SrdStepSums<D>>();
    return sums.has_layers(index_, view.template read<Clock>().step) ? &sums : nullptr;
  }
  const std::vector<double>& layers(const SrdStepSums<D>& sums) const { return sums.layers[index_]; }

 private:
  bool asked_ = false;
  std::size_t index_ = 0;
};

}  // namespace granflow::srd
