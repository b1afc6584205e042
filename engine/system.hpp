#pragma once
// A system names what it reads and writes; the Schedule orders systems from
// those declarations alone, so nobody wires graph edges by hand.

#include <string>
#include <vector>

namespace granflow {

class World;

struct Access {
  std::vector<std::string> reads;
  std::vector<std::string> writes;
};

class System {
 public:
  virtual ~System() = default;
  virtual std::string name() const = 0;
  virtual Access access() const = 0;
  virtual void run(World& world) = 0;
};

}  // namespace granflow
