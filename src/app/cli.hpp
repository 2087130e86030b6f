// The `inkline` command line: parsing and dispatch. Errors are one line on stderr and a
// non-zero exit code (1: bad input or failure, 2: bad usage).
#pragma once

namespace inkline {
int run_cli(int argc, char** argv);
}
