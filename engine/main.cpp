#include "engine/cli.hpp"

int main(int argc, char** argv) { return granflow::command_line_main(argc, argv); }
