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
int run_bench(int argc, char** argv);
// One word of a command line: a positional MODEL (stored in `model`; a second one is a Usage
// error) gives false; `--key=value` gives true and the two parts; `--key` alone is a Usage error.
bool split_option(const std::string& arg, std::string& model, std::string& key, std::string& value);                                 // `inkline bench` (bench.cpp)
}  // namespace inkline
