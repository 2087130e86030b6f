// The sample meshes of the benchmarks, loaded once per process: "name" or "name@N" (N rounds of
// Loop subdivision: armadillo@1 ~208 k, @2 ~832 k triangles), from INKLINE_DATA_DIR.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "pipeline.hpp"

// nullptr when the mesh is not there (scripts/setup.sh extracts them).
inline const inkline::Model* bench_model(const std::string& name) {
    static std::map<std::string, std::unique_ptr<inkline::Model>> cache;
    auto& m = cache[name];
    if (!m) {
        const auto at = name.find('@');
        const int levels = at == std::string::npos ? 0 : std::stoi(name.substr(at + 1));
        const std::string path = std::string(INKLINE_DATA_DIR) + "/meshes/" + name.substr(0, at) + ".off";
        if (!std::filesystem::exists(path)) return nullptr;
        m = std::make_unique<inkline::Model>(inkline::Model::load(path, 40.0, levels));
    }
    return m.get();
}
