// The `inkline` command line: parsing and dispatch. Errors are one line on stderr and a
// non-zero exit code (1: bad input or failure, 2: bad usage).
#pragma once

#include <map>
#include <stdexcept>
#include <string>

namespace inkline {
class Camera;
struct MeshTopology;

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
int run_view(int argc, char** argv);  // `inkline view` (view_cmd.cpp)
// The camera of render's flags (--eye --target --up --fov --size --ortho --near: flag -> value),
// the model framed as in DESIGN.md where unset; Error naming the flag when one is bad.
Camera camera_from_flags(const std::map<std::string, std::string>& flags, const MeshTopology& mesh);
}  // namespace inkline
