// `inkline view` in the `inkline` program: runs the window program installed beside it
// (inkline-window: inkline with the window linked in, whose run_view is app/view_cmd.cpp) with
// the same arguments, so that the other commands start without GLFW's, OpenGL's and X11's
// libraries.
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "app/cli.hpp"
#include "core/error.hpp"

namespace inkline {

int run_view(int argc, char** argv) {
    namespace fs = std::filesystem;
    (void)argc;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    const std::string window = ((ec ? fs::path(".") : exe.parent_path()) / "inkline-window").string();
    execv(window.c_str(), argv);  // returns only when it could not run the program
    throw Error(window, std::string("cannot be run (the window of `inkline view`): ") + std::strerror(errno));
}

}  // namespace inkline
