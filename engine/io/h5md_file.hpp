#pragma once
// Writes H5MD 1.1 result files. The file is built under "<path>.partial" and
// renamed to <path> only by finish(), so an interrupted run never leaves a
// truncated file under the name a user expects to be complete.

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/profiler.hpp"
#include "engine/core/state_map.hpp"
#include "engine/io/h5_handle.hpp"

namespace granflow {

class Config;

class H5mdFile {
 public:
  H5mdFile(const std::string& path, const std::string& scenario);
  ~H5mdFile();
  H5mdFile(const H5mdFile&) = delete;
  H5mdFile& operator=(const H5mdFile&) = delete;

  const std::string& path() const { return path_; }

  void write_parameters(const Config& config);
  // boundary per axis: "periodic" or "none" (H5MD's words). Where particle
  // positions are time-dependent the box is too (one entry per position
  // frame, sharing its step and time), as H5MD readers such as MDAnalysis
  // expect; call it after the last frame.
  void write_box(const std::vector<double>& edges, const std::vector<std::string>& boundary);
  // Time-independent per-particle data, shape [count, components] (components 1 gives [count]).
  void write_particle_constant(const std::string& name, const std::vector<double>& data, std::size_t components,
                               const std::string& unit);
  void write_particle_constant(const std::string& name, const std::vector<std::int32_t>& data);
  // One frame of a time-dependent per-particle element, shape [frames, count, components].
  void append_particle_frame(const std::string& name, std::int64_t step, double time,
                             const std::vector<double>& data, std::size_t components);
  void append_particle_frame(const std::string& name, std::int64_t step, double time,
                             const std::vector<std::int32_t>& data, std::size_t components);
  // The same frame in blocks of rows, for a writer that never holds it
  // whole: begin_particle_frame adds a frame of `count` rows (doubles, or
  // int32 where `integers`), write_particle_rows fills rows [first, first +
  // rows) of the last one. Rows left unwritten read as 0.
  void begin_particle_frame(const std::string& name, std::int64_t step, double time, std::size_t count,
                            std::size_t components, bool integers);
  void write_particle_rows(const std::string& name, std::size_t first, std::size_t rows, const double* data);
  void write_particle_rows(const std::string& name, std::size_t first, std::size_t rows, const std::int32_t* data);
  // The unit of an observable (an H5MD unit string, engine/core/units.hpp), put on
  // its value (and its time in T) when the series is created.
  void declare_unit(const std::string& observable, const std::string& unit) { units_[observable] = unit; }
  void append_observable(const std::string& name, std::int64_t step, double time, double value);
  void append_observable(const std::string& name, std::int64_t step, double time, const std::vector<double>& value);
  // One frame of a field on a grid: /fields/NAME/{step,time,value}, value of
  // `shape` per frame (e.g. cells z, y, x and components).
  void append_field(const std::string& name, std::int64_t step, double time, const std::vector<double>& values,
                    const std::vector<hsize_t>& shape, const std::string& unit);
  // A time-independent result (a histogram and its bin edges, a scan, an
  // average profile): /results/NAME, outside /observables, where H5MD readers
  // such as MDAnalysis expect only {step, time, value} series.
  void write_result(const std::string& name, const std::vector<double>& value, const std::string& unit);
  void write_profile(const std::vector<ProfileEntry>& entries);
  // A plain 1D dataset at group_path/name (for checkpoint state).
  void write_array(const std::string& group_path, const std::string& name, const std::vector<double>& values);
  // The same written in blocks, by a writer that never holds the whole:
  // create_array makes it `count` values long, write_array_block fills
  // [first, first + values.size()).
  void create_array(const std::string& group_path, const std::string& name, std::size_t count);
  void write_array_block(const std::string& group_path, const std::string& name, std::size_t first,
                         const std::vector<double>& values);
  void write_text_array(const std::string& group_path, const std::string& name, const std::vector<std::string>& values);
  void write_attribute(const std::string& group, const std::string& name, const std::string& value);
  void write_attribute(const std::string& group, const std::string& name, double value);
  // The frames written straight to the file (particle frames, fields; not
  // the observables, which the recorder keeps), for a checkpoint; with a
  // `limit` (frame_counts() taken earlier), each series as it was then and
  // none begun since. restore_frames writes them into a resumed run's new
  // file before it writes more.
  StateMap frames_state(const std::map<std::string, std::size_t>* limit = nullptr) const;
  std::map<std::string, std::size_t> frame_counts() const;
  // The particles in the frames of /particles/all/NAME (0 where none was written).
  std::size_t particles_in_frames(const std::string& name) const;
  // With a `limit` (series path -> frames), each series' first frames alone
  // and none of a series it lacks.
  void restore_frames(const StateMap& state, const std::map<std::string, std::size_t>* limit = nullptr);
  // Where the run came from, segment by segment: every segment of a resumed
  // run (command line, version and revision, host, threads, start, end, wall
  // time) is carried in its checkpoints, and the file lists them all under
  // /provenance/segments; the attributes of /provenance are the last one's.
  StateMap provenance_state() const;
  void restore_provenance(const StateMap& state);
  // Writes what the file holds to disk, at most once a second of wall time,
  // so that a reader opening OUTPUT.partial while the run goes on sees every
  // series up to an output round close to the last one. Called after each
  // round of outputs.
  void flush_if_due();
  void flush();
  // Closes the file and moves it to its final name.
  void finish();

 private:
  hid_t group(const std::string& path);
  struct Series;
  void append_observable_frame(const std::string& name, std::int64_t step, double time, const double* value,
                               std::size_t count, const std::vector<hsize_t>& shape);
  void append_to(Series& s, std::int64_t step, double time, const void* value, const std::string& what);
  Series& series(const std::string& group_path, std::size_t value_count, const std::vector<hsize_t>& value_shape,
                 hid_t value_type, const std::string& unit, const std::string& time_unit);

  std::string path_;
  std::string partial_path_;
  H5Handle file_;
  std::map<std::string, H5Handle> groups_;
  std::map<std::string, std::unique_ptr<Series>> series_;
  std::map<std::string, std::string> units_;
  std::chrono::steady_clock::time_point started_;
  std::chrono::steady_clock::time_point last_flush_ = started_;
  std::string started_utc_;
  StateMap earlier_segments_;
  bool finished_ = false;
  int lock_ = -1;  // descriptor holding the exclusive lock on the .partial
};

}  // namespace granflow
