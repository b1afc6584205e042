#pragma once
// The systems `granflow list` names, each with one line. A system's header
// describes it once, beside its class:
//   inline const SystemDescription kinetic_energy_description{"observe_kinetic_energy", "..."};
// so the list holds every system compiled into the program.

#include <map>
#include <string>

namespace granflow {

inline std::map<std::string, std::string>& system_catalogue() {
  static std::map<std::string, std::string> catalogue;
  return catalogue;
}

struct SystemDescription {
  SystemDescription(const std::string& name, const std::string& summary) { system_catalogue()[name] = summary; }
};

}  // namespace granflow
