#pragma once
// What this build is: the project version, the source revision it was built
// from (where the source was a git checkout), and how it was built.

#include <string>

namespace granflow {

struct BuildInfo {
  const char* version;
  const char* revision;
  const char* build_type;
  const char* options;
  const char* compiler;
  const char* flags;
};

const BuildInfo& build_info();
// "granflow 0.1.0 (revision)", and the build on further lines.
std::string version_text();

}  // namespace granflow
