#pragma once
// Keys every scenario has because the Runner uses them: the seed of every
// random stream, and when checkpoints are written.

#include <cstdint>
#include <limits>

#include "engine/core/config.hpp"

namespace granflow {

inline void declare_runner_keys(ConfigSchema& schema) {
  if (!schema.find("run.seed"))
    schema.integer("run.seed", 1, 0, std::numeric_limits<std::int64_t>::max(), "seed of every random stream");
  schema
      .real_or_infinite("output.checkpoint_interval", 600.0, 0.0,
                        "wall-clock seconds between checkpoints (OUTPUT.checkpoint, written after a round of "
                        "outputs; 0: after every round; inf: only when interrupted); ensembles checkpoint after "
                        "every finished run")
      .boolean("output.final_checkpoint", false,
               "keep a checkpoint of the final state, so --resume with a later run.t_stop extends the run");
  schema.allow_change_on_resume("output.checkpoint_interval").allow_change_on_resume("output.final_checkpoint");
}

}  // namespace granflow
