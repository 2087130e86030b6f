// The scene fuzzers' check (fuzz_glb, fuzz_gltf: fuzz/fuzz_scene.cpp), shared with the regression
// tests (tests/test_fuzz_regressions.cpp replays fuzz/regressions/glb-* and gltf-*): a file loaded
// the way inkline loads scenes (load_scene: Assimp, then inkline's checks and repairs), tolerant
// and strict. inkline::Error is the expected answer to bad input, and must be one line naming the
// file. Returns "" when the file was refused that way or loaded into a valid scene, else what is
// wrong; a crash, a sanitizer report, another exception or a hang is a finding too (the fuzzer
// reports those itself).
#pragma once

#include <cmath>
#include <string>

#include <glm/vec3.hpp>

#include "core/error.hpp"
#include "scene/scene.hpp"

namespace inkline_fuzz {

inline bool finite_point(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// What is wrong with an accepted scene ("" when nothing): indices in range, no repeated corner,
// finite positions, an object per face, finite cameras.
inline std::string scene_problem(const inkline::Scene& s) {
    const inkline::TriangleMesh& m = s.mesh;
    if (m.triangles.empty()) return "accepted without faces";
    for (const auto& p : m.positions)
        if (!finite_point(p)) return "non-finite vertex";
    for (const auto& t : m.triangles) {
        for (auto i : t)
            if (i >= m.positions.size()) return "index out of range";
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return "a face repeats a corner";
    }
    if (m.face_object.size() != m.triangles.size()) return "face_object out of step with the faces";
    for (auto o : m.face_object)
        if (o >= m.object_names.size()) return "object id out of range";
    for (const auto& c : s.cameras)
        if (!finite_point(c.eye) || !finite_point(c.target) || !finite_point(c.up) || !std::isfinite(c.fov_deg) ||
            !std::isfinite(c.ortho_height))
            return "non-finite camera '" + c.name + "'";
    return "";
}

inline std::string check_scene_file(const std::string& path) {
    for (bool strict : {false, true}) {
        try {
            const std::string problem = scene_problem(inkline::load_scene(path, inkline::LoadOptions{.strict = strict}));
            if (!problem.empty()) return problem;
        } catch (const inkline::Error& e) {
            const std::string m = e.what();
            if (m.find('\n') != std::string::npos) return "error of several lines: " + m;
            if (m.rfind(path + ": ", 0) != 0) return "error not naming the file first: " + m;
        }
    }
    return "";
}

}  // namespace inkline_fuzz
