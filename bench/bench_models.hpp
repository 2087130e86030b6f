// The sample meshes of the benchmarks, loaded once per process: "name" or "name@N" (N rounds of
// Loop subdivision: armadillo@1 ~208 k, @2 ~832 k triangles), from INKLINE_DATA_DIR.
#pragma once

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/clock.hpp"
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

// bench_model for a command-line tool: nullptr with a message naming `tool` when the mesh is not there.
inline const inkline::Model* bench_model_for(const std::string& name, const char* tool) {
    const inkline::Model* m = bench_model(name);
    if (!m) std::fprintf(stderr, "%s: mesh %s not found (run scripts/setup.sh)\n", tool, name.c_str());
    return m;
}

// The eye of the bench's orbit (src/app/bench.cpp) at `degrees` around: 20 degrees above the
// equator, at the distance that frames the mesh's bounding sphere in a 30-degree view.
inline glm::dvec3 orbit_eye(const inkline::MeshTopology& t, double degrees) {
    const double R = t.bounds.half_diagonal(), D = R / std::sin(15.0 * M_PI / 180.0);
    const double az = degrees * M_PI / 180.0, el = 20.0 * M_PI / 180.0;
    return t.bounds.center() + D * glm::dvec3(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
}

// The items of a comma-separated flag value ("--meshes=a,b"), empty ones skipped.
inline std::vector<std::string> split_commas(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream in(s);
    for (std::string x; std::getline(in, x, ',');)
        if (!x.empty()) out.push_back(x);
    return out;
}

// The process's CPU time (all its threads), ms.
inline double process_cpu_ms() { return 1e3 * inkline::process_cpu_seconds(); }
