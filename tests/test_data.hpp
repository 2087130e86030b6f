// The tests' sample models and standard cameras, named once. Needs INKLINE_DATA_DIR from CMake
// (the folder holding meshes/: Debian's libcgal-demo models).
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <glm/geometric.hpp>

#include "core/camera.hpp"
#include "model/primitives.hpp"
#include "random_camera.hpp"

namespace inkline::test {

// The sample mesh `name`: "armadillo" is INKLINE_DATA_DIR/meshes/armadillo.off; a name with an
// extension ("bunny00.off", "elephant.ply") is taken as it is.
inline std::string mesh_path(const std::string& name) {
    const bool has_extension = name.find('.') != std::string::npos;
    return std::string(INKLINE_DATA_DIR) + "/meshes/" + name + (has_extension ? "" : ".off");
}

// The command line's default camera for a model (DESIGN.md: the bounding box framed from
// normalize(1, 0.6, 1.4), fov 30, up +Y) on a square image of `size` pixels.
inline Camera framed_camera(const Bounds3& box, int size = 1024) { return Camera::framing(box, size, size); }

// Camera k of a test's series over a model: the framed default camera first (k == 0, `rng` left
// untouched), then random_camera's views (near and span as there).
inline Camera framed_then_random(int k, std::mt19937& rng, const Bounds3& box, double near = 0.7, double span = 0.8) {
    return k == 0 ? framed_camera(box) : random_camera(rng, box, near, span);
}

// A unit sphere with a smooth bump (a smaller branch: its own silhouette, cusps where the two
// meet) of `height` and angular `width` in direction `dir`.
inline TriangleMesh bumped_sphere(glm::dvec3 dir, double height, double width) {
    TriangleMesh m = make_sphere({0, 0, 0}, 1.0, 160, 80);
    dir = glm::normalize(dir);
    for (auto& p : m.positions) {
        const glm::dvec3 n = glm::normalize(p);
        const double a = std::acos(std::clamp(glm::dot(n, dir), -1.0, 1.0));
        p = n * (1.0 + height * std::exp(-(a * a) / (width * width)));
    }
    return m;
}

}  // namespace inkline::test
