// Shading strokes (Markosian et al. 97, section 5, fig. 3d): stroke particles placed on the
// surface in world space (one per triangle centre, or by area for an even density), drawn where
// the surface is visible (a ray test from the eye: no layer in front) and where the Lambertian
// tone with a point light at the camera (or, beyond the paper, a chosen directional light) is
// below a threshold. A stroke's direction is
// normal x view ray, so strokes line up with the silhouettes; each is a polyline of a preset world
// length whose segments follow the normal blended from the vertex normals of its triangle.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/camera.hpp"
#include "model/topology.hpp"
#include "style/style.hpp"
#include "visibility/ray_caster.hpp"

namespace inkline {

struct HatchStroke {
    std::uint32_t face = 0;   // the triangle holding the particle
    glm::dvec3 centre{0.0};   // the particle (on the triangle)
    double tone = 0.0;        // Lambertian tone at the particle (light at the camera or chosen)
    std::vector<glm::dvec2> points;  // pixels
};

struct HatchStats {
    std::size_t particles = 0, lit = 0, ray_tests = 0, drawn = 0;
};

// `check_visibility` false skips the ray tests (for tests showing what they remove).
std::vector<HatchStroke> hatch_strokes(const MeshTopology& mesh, const Camera& camera, const RayCaster& rays,
                                       const HatchStyle& style, bool check_visibility = true,
                                       HatchStats* stats = nullptr);

}  // namespace inkline
