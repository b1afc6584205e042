#pragma once
// Version of this build: the project version and, where the source was a git
// checkout, the revision it was built from.

#include <string>

namespace granflow {
std::string version_text();
}
