#pragma once
// RAII ownership of HDF5 identifiers and checked HDF5 calls: every return code
// is tested and a failure names the operation and the object.

#include <hdf5.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace granflow {

class H5Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline hid_t h5_check_id(hid_t id, const std::string& what) {
  if (id < 0) throw H5Error("HDF5 error: " + what);
  return id;
}

inline void h5_check(herr_t status, const std::string& what) {
  if (status < 0) throw H5Error("HDF5 error: " + what);
}

class H5Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  H5Handle() = default;
  H5Handle(hid_t id, Closer closer, const std::string& what) : id_(h5_check_id(id, what)), closer_(closer) {}
  H5Handle(const H5Handle&) = delete;
  H5Handle& operator=(const H5Handle&) = delete;
  H5Handle(H5Handle&& other) noexcept : id_(std::exchange(other.id_, -1)), closer_(other.closer_) {}
  H5Handle& operator=(H5Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, -1);
      closer_ = other.closer_;
    }
    return *this;
  }
  ~H5Handle() { reset(); }

  hid_t get() const { return id_; }
  operator hid_t() const { return id_; }
  bool valid() const { return id_ >= 0; }

  // Closing can fail (a flush to a full disk); close() reports it, the destructor cannot.
  void close(const std::string& what) {
    if (id_ >= 0) h5_check(closer_(std::exchange(id_, -1)), what);
  }

 private:
  void reset() {
    if (id_ >= 0) closer_(std::exchange(id_, -1));
  }
  hid_t id_ = -1;
  Closer closer_ = nullptr;
};

// Silences HDF5's own error printing; granflow reports errors itself.
// Also keeps HDF5 from closing leftover identifiers at process exit: a file
// whose close failed on a full disk stays half-open inside HDF5 1.10, and
// closing it again there crashes (every identifier granflow opens is closed
// by its owner). H5dont_atexit acts only before HDF5's first call.
inline void h5_quiet() {
  static const bool once = [] {
    H5dont_atexit();
    return true;
  }();
  (void)once;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

}  // namespace granflow
