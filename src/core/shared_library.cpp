#include "core/shared_library.hpp"

#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>

#include <dlfcn.h>

#include "core/error.hpp"

#ifndef INKLINE_MODULES_RELATIVE
#define INKLINE_MODULES_RELATIVE "../lib/inkline"
#endif
#ifndef INKLINE_MODULES_INSTALLED
#define INKLINE_MODULES_INSTALLED "/usr/local/lib/inkline"
#endif

namespace inkline {

std::string module_path(const std::string& file_name) {
    namespace fs = std::filesystem;
    if (const char* dir = std::getenv("INKLINE_MODULE_DIR"); dir && *dir) return (fs::path(dir) / file_name).string();
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path beside = (exe.parent_path() / INKLINE_MODULES_RELATIVE / file_name).lexically_normal();
        if (fs::exists(beside, ec)) return beside.string();
    }
    return (fs::path(INKLINE_MODULES_INSTALLED) / file_name).string();
}

void* open_library(const std::string& path, const std::string& purpose) {
    static std::mutex mutex;
    static std::map<std::string, void*> opened;  // never closed: their code may still be on a stack
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto it = opened.find(path); it != opened.end()) return it->second;
    // RTLD_LOCAL: their symbols stay out of the program's namespace (a module's copy of a helper
    // cannot take the place of the program's own).
    void* library = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!library) {
        const char* error = dlerror();
        std::string why = error ? error : "unknown reason";
        if (why.rfind(path + ": ", 0) == 0) why.erase(0, path.size() + 2);  // the path once, at the start
        throw Error(path, "cannot be loaded (" + purpose + "): " + why);
    }
    opened.emplace(path, library);
    return library;
}

void* library_symbol(void* library, const std::string& path, const char* name) {
    dlerror();
    void* symbol = dlsym(library, name);
    if (!symbol) throw Error(path, std::string("has no symbol ") + name + " (a library of another version?)");
    return symbol;
}

}  // namespace inkline
