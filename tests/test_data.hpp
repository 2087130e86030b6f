// The tests' sample models and standard cameras, named once. Needs INKLINE_DATA_DIR from CMake
// (the folder holding meshes/: Debian's libcgal-demo models).
#pragma once

#include <random>
#include <string>

#include "core/camera.hpp"
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

}  // namespace inkline::test
