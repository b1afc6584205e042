#pragma once
// One World's run, as a scenario declares it and as the Runner executes it.
//
// A scenario's build function receives a Run and says, in order: how the
// initial state is made (skipped when resuming: the World comes from the
// checkpoint), which systems advance time (the per-step schedule), which
// observers run when (each with a Trigger), what stops the run, which
// derived quantities and end-of-run outputs it has, and which stateful
// objects a checkpoint must carry. Everything else (output file, clock,
// observable slots and recorder, schedules, profiling, progress, stop
// reasons, checkpoints, interruption) is the Runner's.

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "components/clock.hpp"
#include "engine/core/communicator.hpp"
#include "engine/core/config.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/profiler.hpp"
#include "engine/core/schedule.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/trigger.hpp"
#include "engine/core/world.hpp"
#include "engine/io/checkpoint_file.hpp"
#include "engine/run/observable_recorder.hpp"
#include "engine/run/output_file.hpp"
#include "engine/run/preparation.hpp"
#include "engine/run/run_control.hpp"

namespace granflow {

struct RunOutcome {
  enum class Kind { finished, stopped, failed, interrupted };
  Kind kind = Kind::finished;
  std::string reason;
};

class Run {
 public:
  // `resume_from`: this run's part of a checkpoint, or null for a fresh run.
  // `file`: the result file, or null (ensemble members record in memory).
  Run(const Config& config, Profiler& profiler, std::uint64_t seed, std::size_t member, const StateMap* resume_from,
      H5mdFile* file);
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;

  // --- what a scenario declares ---------------------------------------
  const Config& config() const { return config_; }
  World& world() { return world_; }
  bool resuming() const { return resume_ != nullptr; }
  // The seed of every random stream of this run: run.seed, or an ensemble
  // member's derived seed.
  std::uint64_t seed() const { return seed_; }
  std::size_t member() const { return member_; }

  // Makes the initial state on a fresh run; restores the World's columns and
  // the derived quantities from the checkpoint when resuming.
  void initial_state(const std::function<void(World&)>& create);
  // Over ranks, the particles of a resumed World that this rank keeps (its
  // domain's), told by their position (the `position` column's row): they
  // are read from the checkpoint by block, and no rank holds the whole.
  // The World then holds them in the checkpoint's order (resumed_by_part).
  // Or, where the domain is a range of the checkpoint's order, the rows
  // [first, first + count) of it (`rows`).
  struct OwnedOnResume {
    std::string position;
    std::function<bool(const double* position)> owns;
    std::optional<std::pair<std::size_t, std::size_t>> rows;
  };
  void initial_state(const std::function<void(World&)>& create, const OwnedOnResume& owned);
  bool resumed_by_part() const { return resumed_by_part_; }
  // A kept object's state in the checkpoint being resumed (empty on a fresh
  // run), before the object exists.
  StateMap kept_state_with_rows(const std::string& name) const;
  StateMap kept_state(const std::string& name) const {
    return resume_ ? state_under(*resume_, "kept/" + name) : StateMap{};
  }
  // A quantity computed from the initial state or the configuration, stored
  // under /parameters/derived and carried by checkpoints.
  void derive(const std::string& name, double value);
  double derived(const std::string& name) const;
  const std::vector<std::pair<std::string, double>>& derived_values() const { return derived_; }
  // The H5MD unit of every observable its observers declare one for (after prepare()).
  const std::map<std::string, std::string>& observable_units() const { return observable_units_; }

  // Registers an object whose state a checkpoint carries; when resuming it is
  // restored at once. The object must outlive the run. Its rows that the
  // checkpoint left in the file come with it, unless the World was resumed
  // by part: the object's owner then reads its part of them.
  template <class S>
  S& keep(const std::string& name, S& object) {
    kept_.emplace_back(name, &object);
    if (resume_) object.restore_state(kept_state_with_rows(name));
    return object;
  }

  // A system of the per-step schedule (runs until the next target is reached).
  template <class S, class... Args>
  S& step(Args&&... args) {
    return steps_.emplace<S>(std::forward<Args>(args)...);
  }
  // An observer, run whenever `when` fires.
  template <class S, class... Args>
  S& observe(TriggerPtr when, Args&&... args) {
    add_trigger(when);
    observer_triggers_.push_back(std::move(when));
    return observers_.emplace<S>(std::forward<Args>(args)...);
  }

  void stop_at_time(double t) { stop_time_ = t; }
  void stop_at_step(std::int64_t s) { stop_step_ = s; }
  // Checked after every round of observers: a reason ends the run there.
  void stop_when(std::function<std::optional<std::string>()> criterion) { stop_criteria_.push_back(std::move(criterion)); }
  // The stop reason written when the run reaches its stop time or step.
  void finished_reason(std::string text) { finished_reason_ = std::move(text); }
  // Fraction of the run done by some criterion; progress shows the largest.
  void progress(std::function<double()> fraction) { progress_.push_back(std::move(fraction)); }
  // What the progress rate counts ("collisions/s" with the collision count).
  void rate(std::string unit, std::function<double()> work) {
    rate_unit_ = std::move(unit);
    work_ = std::move(work);
  }
  // Box edges and H5MD boundary words written to /particles/all/box.
  void box(std::vector<double> edges, std::vector<std::string> boundary) {
    box_edges_ = std::move(edges);
    box_boundary_ = std::move(boundary);
  }
  // The ranks this one system is spread over (`mpirun -np K granflow run`),
  // or null: a scenario that offers a distributed step installs it here and
  // refuses what it cannot distribute.
  const Communicator* communicator() const { return communicator_; }
  void on_ranks(const Communicator* communicator) { communicator_ = communicator; }
  // Said by a scenario whose step spreads the system over those ranks.
  void mark_distributed() { distributed_ = true; }
  bool distributed() const { return distributed_; }
  // What a long phase of making the initial state (placement, an
  // equilibration) reports its progress to and watches for interruption.
  Preparation preparation(const std::string& phase) const { return {phase, setup_progress_, interrupt_}; }
  // Output written when the run ends (histograms, totals, a log line); single runs only.
  void at_finish(std::function<void(H5mdFile&, const RunOutcome&)> hook) { finish_hooks_.push_back(std::move(hook)); }
  // One that reads the World's particles or cells: over ranks the whole
  // system is then gathered onto rank 0 for it (else it is not, at the end).
  void at_finish_reading_particles(std::function<void(H5mdFile&, const RunOutcome&)> hook) {
    finish_reads_particles_ = true;
    at_finish(std::move(hook));
  }

  // --- what the Runner uses -------------------------------------------
  // After the scenario's build: creates the observable slots and the
  // recorder, and restores the clock, trigger progress and series when resuming.
  void prepare();
  // Advances to the end, an error or an interruption. `after_round` runs
  // after every round of observers (checkpoints, progress).
  RunOutcome execute(const std::atomic<bool>* interrupt, const std::function<void()>& after_round = {});
  // The run's final state will be saved to be extended (output.final_checkpoint):
  // its round at the stop is split as StopRound says.
  void split_stop_round() { split_stop_round_ = true; }
  // Brings device-resident state to the host first. Over ranks, where
  // `rows` is given and the step can lend this rank's particles, they are
  // not gathered onto rank 0: `rows` gets this rank's rows of the World's
  // columns (write_checkpoint_by_rank), the state the rest.
  StateMap save(RankRows* rows = nullptr);
  // The particle arrays a resumed run's checkpoint left in the file
  // (read_checkpoint's `rows`), or none.
  void resume_rows(const CheckpointRows* rows) { resume_rows_ = rows; }
  const CheckpointRows* resumed_rows() const { return resume_rows_; }
  void write_results(const RunOutcome& outcome);  // box, derived, particle constants, hooks, stop reason
  double progress_fraction() const;
  double work_done() const { return work_ ? work_() : static_cast<double>(world_.resource<Clock>().step); }
  const std::string& rate_unit() const { return rate_unit_; }
  const ObservableRecorder& recorder() const { return *recorder_; }
  const Clock& clock() const { return world_.resource<Clock>(); }
  const std::vector<double>& box_edges() const { return box_edges_; }
  const std::vector<std::string>& box_boundary() const { return box_boundary_; }
  H5mdFile* file() const { return file_; }
  void on_setup_progress(std::function<void(const std::string&, double)> report) { setup_progress_ = std::move(report); }
  // The flag a preparation watches (the Runner's interrupt guard), or null.
  void on_interrupt(const std::atomic<bool>* flag) { interrupt_ = flag; }

 private:
  void add_trigger(const TriggerPtr& trigger);
  // Which observers a round fires: all, or those whose firing is their
  // trigger's own (Trigger::own_firing), or those whose firing the stop set.
  enum class Firing { all, own, set_by_stop };
  void fire(bool stopping, double target_time, std::int64_t target_step, Firing which = Firing::all);
  void fire_at_end();
  void synchronise_host();
  template <class Due>
  void run_observers(Due&& due);
  // Over ranks: whether rank 0 is the one that observes (true without ranks).
  bool observes() const;
  // Over ranks: rank 0's outcome of its observers (stop, failure, reason,
  // and what they asked of the step systems) on every rank.
  void share_observers_outcome();
  bool observe_by_rank(bool reads_particles);
  bool write_particle_constants_by_rank();
  // The step system that lent this rank's particles to the World (null
  // where none can now); `for_checkpoint`: only one whose checkpoints are
  // written by rank. Collective.
  System* lend_part(bool for_checkpoint);
  void take_back_part(System& lending);
  // The first stop criterion met, decided by rank 0 over ranks.
  std::optional<std::string> stop_criterion_met();

  const Config& config_;
  Profiler& profiler_;
  std::uint64_t seed_;
  std::size_t member_;
  const StateMap* resume_;
  const CheckpointRows* resume_rows_ = nullptr;
  bool resumed_by_part_ = false;
  H5mdFile* file_;
  World world_;
  Schedule steps_;
  Schedule observers_;
  std::vector<TriggerPtr> observer_triggers_;
  std::vector<TriggerPtr> triggers_;  // distinct, in declaration order
  std::vector<bool> enabled_;         // observers of the current round
  ObservableRecorder* recorder_ = nullptr;
  std::vector<std::pair<std::string, double>> derived_;
  std::map<std::string, std::string> observable_units_;
  std::vector<std::pair<std::string, Stateful*>> kept_;
  double stop_time_ = std::numeric_limits<double>::infinity();
  std::int64_t stop_step_ = Trigger::no_step;
  std::vector<std::function<std::optional<std::string>()>> stop_criteria_;
  std::string finished_reason_ = "reached run.t_stop";
  std::vector<std::function<double()>> progress_;
  std::string rate_unit_ = "steps/s";
  std::function<double()> work_;
  std::vector<double> box_edges_;
  std::vector<std::string> box_boundary_;
  std::vector<std::function<void(H5mdFile&, const RunOutcome&)>> finish_hooks_;
  bool finish_reads_particles_ = false;
  std::function<void(const std::string&, double)> setup_progress_;
  const std::atomic<bool>* interrupt_ = nullptr;
  const Communicator* communicator_ = nullptr;
  bool distributed_ = false;
  // Time and step of the last round of observers (every trigger has passed them).
  double round_time_ = -std::numeric_limits<double>::infinity();
  std::int64_t round_step_ = -1;
  bool at_end_fired_ = false;
  // How far the observables' series and the file's series (frames) went.
  struct Written {
    ObservableRecorder::SeriesLengths series;
    std::map<std::string, std::size_t> frames;
  };
  Written written() const;
  // A finished run's checkpoint leaves out its final round (at_end): an
  // extension writes its own at its new end.
  std::optional<Written> before_end_;
  // Where the run may be extended, its round at the stop is split: first
  // the observers whose trigger fires there of its own (every step, a
  // period's time), then those whose firing the stop set (the last time of
  // an output list, an end cap). What the latter wrote and changed is told
  // apart in the checkpoint: an extension none of whose own lists has that
  // time leaves it out; one whose lists have it keeps it (observers may
  // read what only the step just taken left, so they cannot fire again).
  struct StopRound {
    double round_time = 0;  // of the round before
    std::int64_t round_step = 0;
    Written before;
    std::vector<std::pair<std::string, StateMap>> kept_before;
  };
  bool split_stop_round_ = false;
  std::optional<StopRound> stop_round_;
  void save_stop_round(StateMap& out) const;
  // On resume: whether the extension's lists leave out the earlier stop
  // (then what the stop set wrote is not replayed and what it kept is undone).
  bool stop_round_left_out();
};

// A scenario's build for 2D and 3D runs, picked by system.dimension:
// `.build = build_by_dimension<build<2>, build<3>>`.
template <void (*Build2)(Run&), void (*Build3)(Run&)>
void build_by_dimension(Run& run) {
  if (run.config().integer("system.dimension") == 2)
    Build2(run);
  else
    Build3(run);
}
// The same for scenarios that also run in 1D.
template <void (*Build1)(Run&), void (*Build2)(Run&), void (*Build3)(Run&)>
void build_by_dimension(Run& run) {
  if (run.config().integer("system.dimension") == 1)
    Build1(run);
  else
    build_by_dimension<Build2, Build3>(run);
}

}  // namespace granflow
