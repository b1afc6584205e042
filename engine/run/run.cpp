#include "engine/run/run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/core/observed_part.hpp"
#include "engine/io/particle_output.hpp"

namespace granflow {

Run::Run(const Config& config, Profiler& profiler, std::uint64_t seed, std::size_t member,
         const StateMap* resume_from, H5mdFile* file)
    : config_(config),
      profiler_(profiler),
      seed_(seed),
      member_(member),
      resume_(resume_from),
      file_(file),
      steps_(profiler),
      observers_(profiler) {
  world_.emplace_resource<Clock>();
  world_.emplace_resource<RunControl>();
  world_.emplace_resource<ObservableStore>();
  world_.emplace_resource<OutputFile>().file = file;
}

void Run::initial_state(const std::function<void(World&)>& create) { initial_state(create, {}); }

namespace {
// Rows of the particle arrays read at once when a rank picks its own.
constexpr std::size_t rows_per_read = std::size_t{1} << 18;
}  // namespace

void Run::initial_state(const std::function<void(World&)>& create, const OwnedOnResume& owned) {
  if (!resume_) {
    create(world_);
    return;
  }
  const auto size = resume_->find("world.size");
  if (size == resume_->end() || size->second.size() != 1 || !(size->second[0] >= 0) || size->second[0] > 4e9)
    throw std::invalid_argument("checkpoint has no valid particle count");
  const auto n = static_cast<std::size_t>(size->second[0]);
  StateMap columns = state_under(*resume_, "world");
  std::size_t kept = n;
  if (resume_rows_ && !resume_rows_->empty()) {
    const auto sizes = resume_rows_->sizes();
    const auto width_of = [&](const std::string& name) {
      const std::size_t values = sizes.at(name);
      if (n == 0 ? values != 0 : values % n != 0)
        throw std::invalid_argument(fmt::format("checkpoint column '{}' holds {} values for {} particles", name,
                                                values, n));
      return n == 0 ? std::size_t{0} : values / n;
    };
    const std::string position = "world/" + owned.position;
    if (owned.rows) {
      // This rank's range of the rows of every column.
      const auto [first, count] = *owned.rows;
      if (first + count > n)
        throw std::invalid_argument(fmt::format("checkpoint rows {}..{} asked of {}", first, first + count, n));
      for (const auto& [name, values] : sizes)
        if (name.starts_with("world/")) {
          const std::size_t w = width_of(name);
          columns[name.substr(6)] = resume_rows_->read(name, first * w, count * w);
        }
      kept = count;
      resumed_by_part_ = true;
    } else if (owned.owns && sizes.count(position)) {
      // This rank's rows, found by their positions, block by block; then
      // the same rows of the other columns.
      const std::size_t width = width_of(position);
      std::vector<std::size_t> mine;
      std::vector<double>& own_positions = columns[owned.position];
      for (std::size_t first = 0; first < n; first += rows_per_read) {
        const std::size_t rows = std::min(rows_per_read, n - first);
        const std::vector<double> x = resume_rows_->read(position, first * width, rows * width);
        for (std::size_t i = 0; i < rows; ++i)
          if (owned.owns(&x[i * width])) {
            mine.push_back(first + i);
            own_positions.insert(own_positions.end(), x.begin() + static_cast<std::ptrdiff_t>(i * width),
                                 x.begin() + static_cast<std::ptrdiff_t>((i + 1) * width));
          }
      }
      for (const auto& [name, values] : sizes) {
        if (name == position || !name.starts_with("world/")) continue;
        const std::size_t w = width_of(name);
        std::vector<double>& out = columns[name.substr(6)];
        out.reserve(mine.size() * w);
        for (std::size_t k = 0; k < mine.size();) {
          const std::size_t first = mine[k] - mine[k] % rows_per_read;
          const std::size_t rows = std::min(rows_per_read, n - first);
          const std::vector<double> block = resume_rows_->read(name, first * w, rows * w);
          for (; k < mine.size() && mine[k] < first + rows; ++k) {
            const auto row = block.begin() + static_cast<std::ptrdiff_t>((mine[k] - first) * w);
            out.insert(out.end(), row, row + static_cast<std::ptrdiff_t>(w));
          }
        }
      }
      kept = mine.size();
      resumed_by_part_ = true;
    } else {
      for (const auto& [name, values] : sizes)
        if (name.starts_with("world/")) columns[name.substr(6)] = resume_rows_->read(name, 0, values);
    }
  }
  world_.restore_columns(kept, columns);
  for (const auto& [name, value] : state_under(*resume_, "derived"))
    if (value.size() == 1) derived_.emplace_back(name, value[0]);
}

StateMap Run::kept_state_with_rows(const std::string& name) const {
  StateMap state = state_under(*resume_, "kept/" + name);
  if (!resume_rows_ || resumed_by_part_) return state;
  const std::string head = "kept/" + name + "/";
  for (const auto& [array, values] : resume_rows_->sizes())
    if (array.starts_with(head)) state[array.substr(head.size())] = resume_rows_->read(array, 0, values);
  return state;
}

void Run::derive(const std::string& name, double value) {
  for (auto& [known, stored] : derived_)
    if (known == name) {
      stored = value;
      return;
    }
  derived_.emplace_back(name, value);
}

double Run::derived(const std::string& name) const {
  for (const auto& [known, value] : derived_)
    if (known == name) return value;
  throw std::logic_error("no derived quantity '" + name + "'");
}

void Run::add_trigger(const TriggerPtr& trigger) {
  if (!trigger) throw std::logic_error("an observer needs a trigger");
  if (std::find(triggers_.begin(), triggers_.end(), trigger) == triggers_.end()) triggers_.push_back(trigger);
}

void Run::prepare() {
  std::vector<std::string> observables;
  auto& store = world_.resource<ObservableStore>();
  for (const auto& system : observers_.systems()) {
    const Access access = system->access();
    for (const auto& name : access.written_observables())
      if (!store.declared(name)) {
        store.declare(name);
        observables.push_back(name);
      }
    for (const auto& [name, unit] : access.observable_units()) {
      observable_units_[name] = unit;
      if (file_) file_->declare_unit(name, unit);
    }
  }
  recorder_ = &observers_.emplace<ObservableRecorder>(observables);
  if (!resume_) return;
  const auto clock = resume_->find("clock");
  const auto round = resume_->find("round");
  if (clock == resume_->end() || clock->second.size() != 2 || round == resume_->end() || round->second.size() != 2)
    throw std::invalid_argument("checkpoint has no clock");
  world_.resource<Clock>().time = clock->second[0];
  world_.resource<Clock>().step = static_cast<std::int64_t>(clock->second[1]);
  round_time_ = round->second[0];
  round_step_ = static_cast<std::int64_t>(round->second[1]);
  const bool leave_out_stop_round = stop_round_left_out();
  for (auto& trigger : triggers_) trigger->pass(round_time_, round_step_);
  if (!leave_out_stop_round) {
    recorder_->replay(file_, state_under(*resume_, "history"));
    if (file_) file_->restore_frames(state_under(*resume_, "frames"));
  } else {
    const auto lengths = [&](const std::string& under) {
      std::map<std::string, std::size_t> out;
      for (const auto& [name, length] : state_under(*resume_, under)) out[name] = static_cast<std::size_t>(length.at(0));
      return out;
    };
    const auto series = lengths("stop_round/series");
    recorder_->replay(file_, state_under(*resume_, "history"), &series);
    const auto frames = lengths("stop_round/frames");
    if (file_) file_->restore_frames(state_under(*resume_, "frames"), &frames);
    for (const auto& [name, object] : kept_)
      if (const StateMap before = state_under(*resume_, "stop_round/kept/" + name); !before.empty())
        object->restore_state(before);
  }
  if (file_) file_->restore_provenance(state_under(*resume_, "provenance"));
}

// The extension's triggers, positioned after the round before the earlier
// stop, are asked whether any fires at the stop other than of its own (an
// output list with that time). What the stop set wrote is kept whole if so:
// observers cannot be told apart in it (where several lists end at the
// stop and one of the longer run's has that time, the others' samples there
// stay).
bool Run::stop_round_left_out() {
  const auto before = resume_->find("stop_round/round");
  if (before == resume_->end()) return false;
  if (before->second.size() != 2) throw std::invalid_argument("checkpoint has a damaged stop round");
  const auto& clock = world_.resource<Clock>();
  for (auto& trigger : triggers_) {
    trigger->pass(before->second[0], static_cast<std::int64_t>(before->second[1]));
    if (trigger->due(clock.time, clock.step) && !trigger->own_firing(clock.time, clock.step)) return false;
  }
  return true;
}

void Run::save_stop_round(StateMap& out) const {
  const StopRound& stop = *stop_round_;
  out["stop_round/round"] = {stop.round_time, static_cast<double>(stop.round_step)};
  for (const auto& [name, length] : stop.before.series) out["stop_round/series/" + name] = {static_cast<double>(length)};
  for (const auto& [path, count] : stop.before.frames) out["stop_round/frames/" + path] = {static_cast<double>(count)};
  for (std::size_t k = 0; k < kept_.size(); ++k) {
    const StateMap& before = stop.kept_before[k].second;
    if (before != kept_[k].second->save_state()) put_state_under(out, "stop_round/kept/" + kept_[k].first, before);
  }
}

void Run::synchronise_host() {
  for (const auto& system : steps_.systems()) system->synchronise_host(world_);
}

StateMap Run::save(RankRows* rows) {
  StateMap out;
  if (rows) *rows = {};
  System* const lending = rows && communicator_ && communicator_->size() > 1 ? lend_part(true) : nullptr;
  if (lending) {
    rows->count = world_.size();
    for (auto& [key, values] : world_.save_columns()) {
      const std::string name = "world/" + key;
      (holds_particle_rows(name) ? rows->arrays : out)[name] = std::move(values);
    }
    // A kept object that holds this rank's part (the step's lists) gives
    // its rows while the part is lent.
    for (const auto& [object_name, object] : kept_) {
      const auto counts = object->state_rows();
      for (auto& [key, values] : object->save_state()) {
        const std::string name = "kept/" + object_name + "/" + key;
        const auto rows_of = counts.find(key);
        if (rows_of == counts.end()) {
          out[name] = std::move(values);
          continue;
        }
        rows->arrays[name] = std::move(values);
        rows->counts[name] = rows_of->second;
      }
    }
    take_back_part(*lending);
    out["world.size"] = {static_cast<double>(communicator_->sum(static_cast<std::int64_t>(rows->count)))};
  } else {
    synchronise_host();
    put_state_under(out, "world", world_.save_columns());
    out["world.size"] = {static_cast<double>(world_.size())};
  }
  const auto& clock = world_.resource<Clock>();
  out["clock"] = {clock.time, static_cast<double>(clock.step)};
  out["round"] = {round_time_, static_cast<double>(round_step_)};
  for (const auto& [name, value] : derived_) out["derived/" + name] = {value};
  if (!lending)
    for (const auto& [name, object] : kept_) put_state_under(out, "kept/" + name, object->save_state());
  const Written* end = at_end_fired_ && before_end_ ? &*before_end_ : nullptr;
  put_state_under(out, "history", end ? recorder_->save_history(end->series) : recorder_->save_history());
  if (file_) put_state_under(out, "frames", file_->frames_state(end ? &end->frames : nullptr));
  if (at_end_fired_ && stop_round_) save_stop_round(out);
  if (file_) put_state_under(out, "provenance", file_->provenance_state());
  return out;
}

// Runs the observers `due` picks (by index), and then the recorder. The
// mask is kept between rounds: time-stepped runs fire every step.
template <class Due>
void Run::run_observers(Due&& due) {
  enabled_.assign(observers_.size(), false);
  bool any = false;
  for (std::size_t k = 0; k < observer_triggers_.size(); ++k) {
    enabled_[k] = due(*observer_triggers_[k]);
    any = any || enabled_[k];
  }
  if (!any) return;
  enabled_.back() = true;  // the recorder, which reads only observables
  const auto& observers = observers_.systems();
  bool reads_device = false;
  for (std::size_t k = 0; k + 1 < observers.size() && !reads_device; ++k)
    reads_device = enabled_[k] && observers[k]->reads_device_state(world_);
  const bool on_ranks = communicator_ && communicator_->size() > 1;
  if (on_ranks) reads_device = communicator_->from_first(reads_device);
  if (on_ranks && observe_by_rank(reads_device)) {
    share_observers_outcome();
    return;
  }
  if (reads_device) synchronise_host();
  if (observes()) observers_.run(world_, enabled_);
  if (on_ranks) share_observers_outcome();
}

// Where every enabled observer can run by rank, each rank observes its own
// particles, which the step lends to the World (ObservedPart says which),
// and no rank gathers the whole. The observers run one at a time, so that
// their collective calls come in one order on every rank. The ranks see
// the same totals and so decide alike; rank 0's decisions are shared all
// the same, as where it alone observes.
bool Run::observe_by_rank(bool reads_particles) {
  const auto& observers = observers_.systems();
  for (std::size_t k = 0; k + 1 < observers.size(); ++k)
    if (enabled_[k] && !observers[k]->observes_by_rank()) return false;
  System* const lending = reads_particles ? lend_part(false) : nullptr;
  if (reads_particles && !lending) return false;
  observers_.run_in_order(world_, enabled_);
  if (lending) take_back_part(*lending);
  return true;
}

System* Run::lend_part(bool for_checkpoint) {
  for (const auto& system : steps_.systems())
    if (system->lend_part(world_)) {
      if (for_checkpoint) system->lend_checkpoint_state(world_);
      return system.get();
    }
  return nullptr;
}

void Run::take_back_part(System& lending) {
  world_.emplace_resource<ObservedPart>();
  lending.take_back_part(world_);
}

namespace {
// A text as values of a broadcast, one character each, and back.
void append_text(std::vector<double>& values, const std::string& text) {
  for (const char c : text) values.push_back(static_cast<unsigned char>(c));
}
std::string text_of(std::vector<double>::const_iterator first, std::size_t length) {
  std::string text;
  for (std::size_t k = 0; k < length; ++k) text.push_back(static_cast<char>(static_cast<unsigned char>(first[k])));
  return text;
}
}  // namespace

bool Run::observes() const { return !communicator_ || communicator_->size() < 2 || communicator_->rank() == 0; }

// One message from rank 0: [stop, failed, reason's length, its characters,
// then per step system the length of its requests and them].
void Run::share_observers_outcome() {
  auto& control = world_.resource<RunControl>();
  std::vector<double> message;
  if (communicator_->rank() == 0) {
    message = {control.stop ? 1.0 : 0.0, control.failed ? 1.0 : 0.0, static_cast<double>(control.reason.size())};
    append_text(message, control.reason);
    for (const auto& system : steps_.systems()) {
      const std::vector<double> asked = system->observers_requests(world_);
      message.push_back(static_cast<double>(asked.size()));
      message.insert(message.end(), asked.begin(), asked.end());
    }
  }
  message = communicator_->values_from_first(message);
  if (communicator_->rank() == 0) return;
  control.stop = message[0] != 0.0;
  control.failed = message[1] != 0.0;
  const auto length = static_cast<std::size_t>(message[2]);
  control.reason = text_of(message.begin() + 3, length);
  std::size_t at = 3 + length;
  for (const auto& system : steps_.systems()) {
    const auto count = static_cast<std::size_t>(message[at]);
    const auto first = message.begin() + static_cast<std::ptrdiff_t>(at + 1);
    system->adopt_observers_requests(world_, std::vector<double>(first, first + static_cast<std::ptrdiff_t>(count)));
    at += 1 + count;
  }
}

std::optional<std::string> Run::stop_criterion_met() {
  if (stop_criteria_.empty()) return std::nullopt;
  std::optional<std::string> met;
  if (observes())
    for (const auto& criterion : stop_criteria_)
      if ((met = criterion())) break;
  if (!communicator_ || communicator_->size() < 2) return met;
  std::vector<double> message;
  if (met) append_text(message, *met);
  if (!communicator_->from_first(met.has_value())) return std::nullopt;
  message = communicator_->values_from_first(message);
  return text_of(message.begin(), message.size());
}

// Observers whose trigger is due at the clock run; at a stop, so do those
// that were due at the target the run was heading for.
void Run::fire(bool stopping, double target_time, std::int64_t target_step, Firing which) {
  const auto& clock = world_.resource<Clock>();
  run_observers([&](const Trigger& t) {
    if (which != Firing::all && t.own_firing(clock.time, clock.step) != (which == Firing::own)) return false;
    bool due = t.due(clock.time, clock.step);
    if (stopping)
      due = due || (t.next_time() != Trigger::never && time_reached(t.next_time(), target_time)) ||
            (t.next_step() != Trigger::no_step && t.next_step() <= target_step);
    return due;
  });
}

Run::Written Run::written() const {
  Written out;
  out.series = recorder_->lengths();
  if (file_) out.frames = file_->frame_counts();
  return out;
}

void Run::fire_at_end() {
  if (at_end_fired_) return;
  at_end_fired_ = true;
  before_end_ = written();
  auto& control = world_.resource<RunControl>();
  control.ending = true;
  run_observers([](const Trigger& t) { return t.at_end(); });
  control.ending = false;
}

RunOutcome Run::execute(const std::atomic<bool>* interrupt, const std::function<void()>& after_round) {
  auto& clock = world_.resource<Clock>();
  auto& control = world_.resource<RunControl>();
  control.interrupt = interrupt;
  const auto interrupted = [&] { return interrupt && interrupt->load(std::memory_order_relaxed); };
  while (true) {
    if (interrupted()) return {RunOutcome::Kind::interrupted, "interrupted"};
    // The next target: the earliest time and step any trigger asks for, up
    // to the stop time and step. Times that agree to round-off are one
    // target, at the time of the first-declared trigger among them.
    double earliest = stop_time_;
    std::int64_t target_step = stop_step_;
    for (const auto& t : triggers_) {
      earliest = std::min(earliest, t->next_time());
      target_step = std::min(target_step, t->next_step());
    }
    double target_time = earliest;
    for (const auto& t : triggers_)
      if (time_reached(t->next_time(), earliest)) {
        target_time = std::min(t->next_time(), stop_time_);
        break;
      }
    if (!std::isfinite(target_time) && target_step == Trigger::no_step) break;  // nothing left to wait for
    control.target_time = target_time;
    control.target_step = target_step;
    while (clock.time < target_time && clock.step < target_step && !control.stop) {
      const double time_before = clock.time;
      const std::int64_t step_before = clock.step;
      steps_.run(world_);
      if (interrupted() && clock.time < target_time && clock.step < target_step && !control.stop)
        return {RunOutcome::Kind::interrupted, "interrupted"};
      if (clock.time == time_before && clock.step == step_before && !control.stop)
        throw std::logic_error("the per-step systems did not advance the clock");
    }
    if (split_stop_round_ && !stop_round_ && !control.stop && (clock.time >= stop_time_ || clock.step >= stop_step_)) {
      fire(false, target_time, target_step, Firing::own);
      StopRound& stop = stop_round_.emplace();
      stop.round_time = round_time_;
      stop.round_step = round_step_;
      stop.before = written();
      // Over ranks a step may hold what its last step owes kept objects (the
      // soft spheres' energy terms, added at the next gather): lending the
      // part settles it, as the checkpoint's own lending will, and where the
      // step cannot lend, the gather the checkpoint will then make.
      if (communicator_ && communicator_->size() > 1) {
        if (System* const lending = lend_part(false)) take_back_part(*lending);
        else synchronise_host();
      }
      for (const auto& [name, object] : kept_) stop.kept_before.emplace_back(name, object->save_state());
      fire(control.stop, target_time, target_step, Firing::set_by_stop);
    } else {
      fire(control.stop, target_time, target_step);
    }
    round_time_ = clock.time;
    round_step_ = clock.step;
    for (auto& t : triggers_) t->pass(clock.time, clock.step);
    if (control.stop) {
      fire_at_end();
      return {control.failed ? RunOutcome::Kind::failed : RunOutcome::Kind::stopped, control.reason};
    }
    if (clock.time >= stop_time_ || clock.step >= stop_step_) break;
    if (auto reason = stop_criterion_met()) {
      fire_at_end();
      return {RunOutcome::Kind::finished, *reason};
    }
    if (after_round) after_round();
  }
  fire_at_end();
  return {RunOutcome::Kind::finished, finished_reason_};
}

double Run::progress_fraction() const {
  const auto& clock = world_.resource<Clock>();
  double fraction = 0.0;
  if (std::isfinite(stop_time_) && stop_time_ > 0) fraction = std::max(fraction, clock.time / stop_time_);
  if (stop_step_ != Trigger::no_step && stop_step_ > 0)
    fraction = std::max(fraction, static_cast<double>(clock.step) / static_cast<double>(stop_step_));
  for (const auto& f : progress_) fraction = std::max(fraction, f());
  return std::clamp(fraction, 0.0, 1.0);
}

// Over ranks, where the step lends each rank its particles and they carry
// their ids, the particle constants are written from the parts: without a
// gather of the whole. Collective.
bool Run::write_particle_constants_by_rank() {
  if (!world_.has_component<Mass>() || !world_.has_component<ParticleId>()) return false;
  System* const lending = lend_part(false);
  if (!lending) return false;
  granflow::write_particle_constants_by_rank(file_, ParticleConstantsView(world_), world_.resource<ObservedPart>());
  take_back_part(*lending);
  return true;
}

void Run::write_results(const RunOutcome& outcome) {
  const bool on_ranks = communicator_ && communicator_->size() > 1;
  const bool constants_written = on_ranks && !finish_reads_particles_ && write_particle_constants_by_rank();
  if (!on_ranks || finish_reads_particles_ || (world_.has_component<Mass>() && !constants_written)) synchronise_host();
  for (const auto& system : steps_.systems())
    for (const ProfileEntry& entry : system->device_profile()) profiler_.record_device(entry);
  if (!file_) return;
  if (!box_edges_.empty()) file_->write_box(box_edges_, box_boundary_);
  for (const auto& [name, value] : derived_) file_->write_attribute("/parameters/derived", name, value);
  if (!constants_written && world_.size() > 0 && world_.has_component<Mass>()) write_particle_constants(*file_, world_);
  for (const auto& hook : finish_hooks_) hook(*file_, outcome);
  file_->write_attribute("/observables", "stop_reason", outcome.reason);
}

}  // namespace granflow
