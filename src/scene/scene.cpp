// load_scene: the Assimp module's reading (scene_reader.hpp, opened at the first scene file), then
// what inkline checks and repairs in every format: the cameras that can make a view, repair_mesh.
#include "scene/scene.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

#include "core/error.hpp"
#include "core/shared_library.hpp"
#include "model/load_progress.hpp"
#include "scene/scene_reader.hpp"

// Defined only in a program that links assimp_reader.cpp itself (the fuzzers: fuzz/run.sh).
extern "C" const inkline::SceneReader* inkline_scene_reader_v1() __attribute__((weak));

namespace inkline {
namespace {

const SceneReader& scene_reader() {
    static const SceneReader* const reader = [] {
        if (inkline_scene_reader_v1) return inkline_scene_reader_v1();
        const std::string path = module_path(kSceneReaderModule);
        void* library = open_library(path, "Assimp's reader of the scene formats; $INKLINE_MODULE_DIR names its folder");
        using Entry = const SceneReader* (*)();
        return reinterpret_cast<Entry>(library_symbol(library, path, kSceneReaderSymbol))();
    }();
    return *reader;
}

std::string lower_extension(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
    return e;
}

// In tolerant mode the cameras that cannot make a view (a zero field of view, the eye on the
// target, NaN: glTF forbids them, Assimp passes them on) are dropped and counted, in strict mode
// refused by name.
void keep_usable_cameras(std::vector<SceneCamera>& cameras, const std::string& path, bool strict, LoadReport& report) {
    std::vector<SceneCamera> kept;
    for (SceneCamera& c : cameras) {
        try {
            (void)c.to_camera(100, 100);
            kept.push_back(std::move(c));
        } catch (const Error& e) {
            if (strict) throw Error(path, e.what());
            if (report.cameras_dropped++ == 0) report.first_camera_problem = e.what();
        }
    }
    cameras = std::move(kept);
}

}  // namespace

Camera SceneCamera::to_camera(int width, int height) const {
    try {
        if (orthographic) return Camera::orthographic(eye, target, up, ortho_height, width, height);
        return Camera::perspective(eye, target, up, fov_deg, width, height);
    } catch (const std::invalid_argument& e) {
        throw Error("camera '" + name + "'", e.what());
    }
}

bool is_scene_file(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext.size() < 2 || ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl") return false;
    return scene_reader().reads_extension(ext);
}

Scene load_scene(const std::string& path, const LoadOptions& options) {
    std::uint64_t progress_bytes = 0;
    Scene out = scene_reader().read(path, options, progress_bytes);
    keep_usable_cameras(out.cameras, path, options.strict, out.mesh.repairs);
    repair_mesh(out.mesh, path, options);
    LoadProgressReporter(&options.progress, progress_bytes).stage(kProgressRepaired);
    return out;
}

}  // namespace inkline
