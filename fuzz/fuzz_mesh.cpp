// libFuzzer target: one mesh format (FUZZ_EXT: off, obj, ply, stl) through inkline's own loading
// path (load_mesh: the strict readers, then validation). The input is written to a private
// temporary file with that extension, since load_mesh takes a path. inkline::Error is the
// expected answer to bad input; anything else (a crash, a sanitizer report, another exception,
// a timeout, more than -rss_limit_mb of memory) is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "model/mesh_io.hpp"

#ifndef FUZZ_EXT
#error "define FUZZ_EXT"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string path =
        "/tmp/inkline_fuzz_" + std::to_string(::getpid()) + "." + std::string(FUZZ_EXT);
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return 0;
    if (size) std::fwrite(data, 1, size, f);
    std::fclose(f);
    try {
        const inkline::TriangleMesh m = inkline::load_mesh(path);
        // Accepted meshes are valid: every index in range, no repeated corner.
        for (const auto& t : m.triangles)
            for (auto i : t)
                if (i >= m.positions.size()) __builtin_trap();
    } catch (const inkline::Error&) {
    }
    return 0;
}
