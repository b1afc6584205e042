#pragma once
// A system names what it reads and writes (engine/core/access.hpp); the Schedule
// orders systems from those declarations alone, so nobody wires graph edges
// by hand.

#include <string>
#include <vector>

#include "engine/core/access.hpp"
#include "engine/core/profiler.hpp"

namespace granflow {

class World;

class System {
 public:
  virtual ~System() = default;
  virtual std::string name() const = 0;
  virtual Access access() const = 0;
  virtual void run(World& world) = 0;

  // For a system whose state lives on an accelerator: bring the World's
  // columns and resources up to date, before observers or a checkpoint read
  // them (the Run calls it; between such times the state stays there).
  virtual void synchronise_host(World&) {}
  // For an observer: whether this round it reads state that lives on an
  // accelerator (particle columns). One that reads only what the step keeps
  // current on the host (sums it computed there, counters) says no, and a
  // round of only such observers copies nothing back.
  virtual bool reads_device_state(const World&) const { return true; }
  // Its stages as the accelerator's own clock timed them: the wall time of
  // an asynchronous launch says nothing. Added to the /profile table.
  virtual std::vector<ProfileEntry> device_profile() const { return {}; }

  // Over MPI ranks the observers run on rank 0 alone where it gathered the
  // whole system (the others hold only their part of it). What they asked
  // of a step system in the World (sums it should compute every step) goes
  // to the other ranks as rank 0's `observers_requests`, which they
  // `adopt_observers_requests`.
  virtual std::vector<double> observers_requests(const World&) const { return {}; }
  virtual void adopt_observers_requests(World&, const std::vector<double>&) {}

  // Unless every observer of a round can run on each rank over the rank's
  // own particles: one that says so totals its sums over the ranks through
  // View::part() (engine/core/observed_part.hpp), and writes only where
  // part().writes(). Such a round gathers nothing.
  virtual bool observes_by_rank() const { return false; }
  // For a step system spread over ranks: put this rank's own particles, and
  // this step's cells of its grid, into the World for such a round (false:
  // it cannot now, and the round gathers onto rank 0); take_back_part
  // returns them to the step afterwards. Collective.
  virtual bool lend_part(World&) { return false; }
  virtual void take_back_part(World&) {}
  // For a checkpoint written by rank (write_checkpoint_by_rank), after
  // lend_part: what else of this rank's part the checkpoint carries (the
  // step's lists), lent to the World's kept objects, which give it as rows
  // (Stateful::state_rows); take_back_part takes it back.
  virtual void lend_checkpoint_state(World&) {}
};

}  // namespace granflow
