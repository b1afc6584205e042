#pragma once
// A system names what it reads and writes (engine/access.hpp); the Schedule
// orders systems from those declarations alone, so nobody wires graph edges
// by hand.

#include <string>

#include "engine/access.hpp"

namespace granflow {

class World;

class System {
 public:
  virtual ~System() = default;
  virtual std::string name() const = 0;
  virtual Access access() const = 0;
  virtual void run(World& world) = 0;
};

}  // namespace granflow
