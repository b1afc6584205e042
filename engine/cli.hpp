#pragma once
// The granflow command line: run, list, info, keys.

namespace granflow {
int command_line_main(int argc, char** argv);
}
