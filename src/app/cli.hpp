// The `inkline` command line: parsing and dispatch. Errors are one line on stderr and a
// non-zero exit code (1: bad input or failure, 2: bad usage).
#pragma once

#include <stdexcept>
#include <string>

namespace inkline {
int run_cli(int argc, char** argv);

// Shared by the commands.
struct Usage : std::runtime_error {
    using std::runtime_error::runtime_error;
};
double parse_number(const std::string& flag, const std::string& s);  // finite, or Error naming flag
int run_bench(int argc, char** argv);                                 // `inkline bench` (bench.cpp)
}  // namespace inkline
