#include "engine/app/cli.hpp"

int main(int argc, char** argv) { return granflow::main(argc, argv); }
