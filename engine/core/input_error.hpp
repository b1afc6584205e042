#pragma once
// Every error that means "the input is wrong" (a configuration key, a value,
// a file that cannot be used as asked) derives from InputError, so the command
// line reports them all the same way: a message on standard error and exit
// status 2, whichever layer found the problem.

#include <stdexcept>

namespace granflow {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace granflow
