#pragma once
// The result file of a run as a World resource, so systems that write it
// (observable recorder, particle frames) declare that and never run at the
// same time. Members of an ensemble have none: `file` is null and they only
// record in memory.

#include "engine/io/h5md_file.hpp"

namespace granflow {

struct OutputFile {
  static constexpr const char* key = "output_file";
  H5mdFile* file = nullptr;
};

}  // namespace granflow
