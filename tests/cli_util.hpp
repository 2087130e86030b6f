// Running the `inkline` command from tests: a scratch directory per test, the exit code and what
// the command printed. Needs INKLINE_BINARY (and INKLINE_DATA_DIR for mesh()) from CMake.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>
#include <sys/wait.h>

namespace inkline_test {

namespace fs = std::filesystem;

struct Result {
    int code = -1;
    std::string out, err;
};

inline std::string slurp(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

// An empty directory named after the running test (and `prefix`, the test file's) and the
// process (test suites of several checkouts may run at once on one machine).
inline fs::path scratch(const std::string& prefix) {
    const fs::path d = fs::path(::testing::TempDir()) /
                       (prefix + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
                        std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

// Runs `<before>inkline <args>` through the shell (`before`: environment assignments or a wrapper
// such as xvfb-run, ending in a space), its output kept in `dir`.
inline Result run_inkline(const std::string& before, const std::string& args, const fs::path& dir) {
    const std::string cmd = before + std::string(INKLINE_BINARY) + " " + args + " >" + (dir / "stdout").string() +
                            " 2>" + (dir / "stderr").string();
    const int status = std::system(cmd.c_str());
    Result r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(dir / "stdout");
    r.err = slurp(dir / "stderr");
    return r;
}

}  // namespace inkline_test
