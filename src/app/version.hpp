// What `inkline --version` prints after "inkline ": CMake's project(VERSION), and when built from a
// git checkout its revision ("0.1.0 (git 1a2b3c4d5e)"); generated at build time (cmake/revision.cmake).
#pragma once

namespace inkline {
const char* version_text();
}
