// Libraries that only some commands need, opened at their first use (dlopen) instead of at
// start-up: a render to SVG then pays nothing for Assimp's, Cairo's or OpenGL's libraries
// (docs/loading.md, "Start-up"). Takes a library's file name; gives its handle and symbols, or
// one inkline::Error line naming the library that is missing and what needs it.
#pragma once

#include <string>

namespace inkline {

// The folder of inkline's own modules (libinkline_assimp.so): $INKLINE_MODULE_DIR when set, else
// the one beside the running program as installed (the build tree mirrors it), else the folder
// the project was configured to install them in (programs linking the library, anywhere).
std::string module_path(const std::string& file_name);

// dlopen(path) once per path (later calls give the same handle). `purpose` says what needs it, for
// the error: "<path>: cannot be loaded (<purpose>): <the loader's words>".
void* open_library(const std::string& path, const std::string& purpose);

// The symbol `name` of a library opened by open_library; throws inkline::Error naming both when
// it is not there (a library of another version).
void* library_symbol(void* library, const std::string& path, const char* name);

}  // namespace inkline
