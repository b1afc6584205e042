#pragma once
// A directory of the test process's own under the system's temporary one,
// removed with everything in it when it goes: tests of two checkouts, or a
// test's CI and long variants, may run at once on one machine.

#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace granflow {

struct ScratchDirectory {
  explicit ScratchDirectory(const std::string& prefix)
      : path(std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path);
  }
  ~ScratchDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;
  std::filesystem::path path;
};

}  // namespace granflow
