#pragma once
// The keys of the SDE family, declared once: the model's parameters (sde.*,
// or those of the hard-sphere gas they come from, gas.*) and the stepping
// (run.dt, run.scheme), each with its from(Config).

#include <cmath>
#include <limits>

#include "engine/core/config.hpp"
#include "systems/sde/sde_kernel.hpp"
#include "systems/sde/sde_model.hpp"
#include "systems/sde/sde_theory.hpp"

namespace granflow::sde {

// `scaled`: underdamped scaled Brownian motion, whose gamma and D decay with tau0.
inline void declare_sde_model_keys(ConfigSchema& s, bool scaled) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  s.choice("sde.parameters", "gas", {"gas", "direct"},
           "gas: gamma0, D0 (Enskog) and tau0 (Haff) of the hard-sphere gas gas.*, gamma0 = T0 / (m D0); "
           "direct: sde.*")
      .real("sde.gamma0", 10.0, 0.0, inf, "friction coefficient gamma0 (sde.parameters = direct)", true)
      .real("sde.diffusivity0", 0.05, 0.0, inf, "diffusivity D0 (sde.parameters = direct)", true)
      .real("gas.count", 1000.0, 0.0, inf, "N of the gas the parameters come from", true)
      .real("gas.radius", 0.025, 0.0, inf, "particle radius r of that gas", true)
      .real("gas.box_length", 1.0, 0.0, inf, "edge of its cubic box", true)
      .real("gas.temperature", 2.0 / 3.0, 0.0, inf, "its initial temperature T0 (2/3: speed sqrt(2))", true)
      .real("gas.mass", 1.0, 0.0, inf, "particle mass m", true);
  if (scaled)
    s.real("gas.restitution", 0.8, 0.0, 1.0, "restitution xi of that gas (xi < 1: UDSBM; sets tau0)")
        .real("sde.tau0", 1.0, 0.0, inf, "decay time tau0 of gamma and D (sde.parameters = direct)", true);
}

// The model a configuration asks for (from the gas or given directly).
inline SdeModel sde_model_from(const Config& config) {
  const bool scaled = config.schema().find("sde.tau0") != nullptr;
  SdeModel model;
  if (config.text("sde.parameters") == "direct") {
    model.gamma0 = config.real("sde.gamma0");
    model.diffusivity0 = config.real("sde.diffusivity0");
    if (scaled) model.tau0 = config.real("sde.tau0");
  } else {
    const double xi = scaled ? config.real("gas.restitution") : 1.0;
    model = model_from_gas(config.real("gas.count"), config.real("gas.radius"), xi,
                                config.real("gas.temperature"), config.real("gas.mass"),
                                std::pow(config.real("gas.box_length"), 3));
    if (!scaled) model.tau0 = std::numeric_limits<double>::infinity();
  }
  if (model.scaled() && std::abs(model.gamma0 * model.tau0 - 1.0) < 1e-9)
    throw ConfigError("gamma0 * tau0 = 1 is the degenerate case of UDSBM's MSD; choose other parameters");
  return model;
}

inline void declare_sde_step_keys(ConfigSchema& s) {
  s.real("run.dt", 0.01, 0.0, std::numeric_limits<double>::infinity(), "time step", true)
      .choice("run.scheme", "exact_ou", {"exact_ou", "euler_maruyama"},
              "exact_ou: exact Ornstein-Uhlenbeck velocity update between half drifts (BAOAB-style); "
              "euler_maruyama: the first-order scheme (Kloeden & Platen 1992)");
}

inline Scheme scheme_from(const Config& config) {
  return config.text("run.scheme") == "euler_maruyama" ? Scheme::euler_maruyama : Scheme::exact_ou;
}

}  // namespace granflow::sde
