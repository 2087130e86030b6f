// The Assimp side of load_scene (scene.hpp), built as a module of its own (libinkline_assimp.so,
// opened at the first scene file: core/shared_library.hpp) so that programs reading only OBJ,
// OFF, PLY and STL never load Assimp. Takes a file path; gives the scene's triangles placed by
// their nodes with their objects, and every camera of the file, before inkline's repairs and
// camera checks (which stay in the program: scene.cpp). Same compiler and standard library on
// both sides: the module is built with the program from the same tree.
#pragma once

#include <cstdint>
#include <string>

#include "model/mesh_io.hpp"
#include "scene/scene.hpp"

namespace inkline {

class SceneReader {
public:
    // True for an extension (".glb", lower case) that Assimp reads.
    virtual bool reads_extension(const std::string& extension) const = 0;
    // Throws inkline::Error("<file>: <problem>") for anything it cannot read (scene.hpp's list).
    // Reports progress up to kProgressParsed; *progress_bytes is the size the progress counts.
    virtual Scene read(const std::string& path, const LoadOptions& options, std::uint64_t& progress_bytes) const = 0;

protected:
    ~SceneReader() = default;  // the module's one reader lives as long as the module
};

// The module's one exported symbol: extern "C" const SceneReader* inkline_scene_reader_v1().
inline constexpr const char* kSceneReaderSymbol = "inkline_scene_reader_v1";
inline constexpr const char* kSceneReaderModule = "libinkline_assimp.so";

}  // namespace inkline
