// libFuzzer target: glTF 2.0 through inkline's scene loading (load_scene: Assimp's reader, then
// inkline's structure checks, node graph and repairs), as a binary .glb or a .gltf text (FUZZ_EXT:
// glb or gltf). The input is written to a private temporary file with that extension, since
// load_scene takes a path; the check is fuzz/scene_checks.hpp. Assimp itself is not instrumented:
// coverage guides the fuzzer through inkline's code only, and ASan sees Assimp's heap misuse only
// where it frees or allocates (its reads and writes are not checked).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "scene_checks.hpp"

#ifndef FUZZ_EXT
#error "define FUZZ_EXT (glb or gltf)"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string path = "/tmp/inkline_fuzz_" + std::to_string(::getpid()) + "." + std::string(FUZZ_EXT);
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return 0;
    if (size) std::fwrite(data, 1, size, f);
    std::fclose(f);
    const std::string problem = inkline_fuzz::check_scene_file(path);
    if (!problem.empty()) {
        std::fprintf(stderr, "fuzz_%s: %s\n", FUZZ_EXT, problem.c_str());
        __builtin_trap();
    }
    return 0;
}
