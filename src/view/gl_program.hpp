// OpenGL helpers shared by the preview window's passes (a current GL 3.3 core context is needed
// for gl_program).
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/camera.hpp"

namespace inkline {

// The program of a vertex and a fragment shader (GLSL source); a compile or link error is thrown
// as Error("view", ...) with the driver's log.
unsigned gl_program(const char* vertex_source, const char* fragment_source);

// The view and projection of `cam` for vertices uploaded relative to `centre` (so float precision
// holds far from the origin), near and far around the bounding sphere of `radius` there; every
// pass that draws the mesh uses these, so their depths agree.
struct GlCameraMatrices {
    glm::mat4 view, projection;
};
GlCameraMatrices gl_camera_matrices(const Camera& cam, const glm::dvec3& centre, double radius, double aspect);

}  // namespace inkline
