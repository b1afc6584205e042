#pragma once
// The granflow command line: run, sweep, list, keys, info, --version.
//
// A program of your own that registers scenarios (GRANFLOW_REGISTER_SCENARIO)
// gets the whole command line for them and the built-in ones with
//   int main(int argc, char** argv) { return granflow::main(argc, argv); }

namespace granflow {

int main(int argc, char** argv);

// Defined by the build's generated list of built-in scenarios; calling it
// keeps them in a program linked against the static libraries.
void link_builtin_scenarios();

}  // namespace granflow
