#pragma once
// Where a scenario made of independent runs saves the runs it has finished,
// and whether to continue from them (--resume): an interruption loses only
// the runs in progress.

#include <string>

namespace granflow::scenarios {

struct RunCheckpoint {
  std::string path;  // empty: no checkpoints
  bool resume = false;
};

}  // namespace granflow::scenarios
