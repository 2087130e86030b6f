// The `inkline` command line: dispatch to the commands. Errors are one line on stderr and a
// non-zero exit code (1: bad input, bad value or failure; 2: bad usage, with a pointer to --help).
// The flags the commands share are defined once, in app/flags.hpp.
#pragma once

namespace inkline {

int run_cli(int argc, char** argv);

int run_render(int argc, char** argv);  // `inkline render` (cli.cpp)
int run_bench(int argc, char** argv);   // `inkline bench` (bench.cpp)
int run_view(int argc, char** argv);    // `inkline view` (view_cmd.cpp)

}  // namespace inkline
