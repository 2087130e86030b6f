// Per-view curvature quantities (DeCarlo et al. 2003, 2004), with the conventions of Rusinkiewicz's
// real-time suggestive contours (rtsc), so that our zero sets and tests agree with that reference:
//
//   v      unit vector from the vertex to the eye (orthographic: -forward, the same everywhere)
//   theta  angle between n and v;  w = v - (n.v) n, |w| = sin(theta)
//   u, t   v . dir1, v . dir2: the components of w in the principal frame (u^2 + t^2 = sin^2)
//
//   kr     = k1 u^2 + k2 t^2 = (radial curvature along w) * sin^2(theta). The positive factor
//            keeps the zero set and sign and avoids dividing by sin^2, which vanishes head-on.
//   dwkr   = D_w kr, the derivative of the radial curvature along w itself (not along w/|w|):
//            sin(theta) C(w^,w^,w^) - 2 cos(theta) tau^2, with w^ = w/|w| and
//            tau = (k2 - k1) cos(phi) sin(phi) the geodesic torsion along w^ (the second term is
//            the turning of w as one moves: DeCarlo et al. 2004, eq. for D_w kappa_r). Only its
//            sign and its ratio to n.v are used (surface_lines.cpp), so no sin^2 appears in it.
#include <algorithm>
#include <cmath>

#include "curvature/curvature.hpp"

namespace inkline {

void compute_view_curvature(const CurvatureField& field, const MeshTopology& mesh, const Camera& camera,
                            ViewCurvature& out) {
    const std::size_t n = std::min(field.size(), mesh.vertex_count());
    out.ndotv.resize(n);
    out.kr.resize(n);
    out.dwkr.resize(n);
    const bool ortho = camera.is_ortho();
    const glm::dvec3 eye = camera.eye();
    const glm::vec3 to_eye_ortho = glm::vec3(-camera.forward());
    const glm::dvec3* pos = mesh.positions.data();
    const glm::vec3* normal = field.normal.data();
    const glm::vec3* dir1 = field.dir1.data();
    const float* k1 = field.k1.data();
    const float* k2 = field.k2.data();
    const std::array<float, 4>* dcurv = field.dcurv.data();
    float* ndotv = out.ndotv.data();
    float* kr = out.kr.data();
    float* dwkr = out.dwkr.data();
    for (std::size_t i = 0; i < n; ++i) {
        glm::vec3 v = to_eye_ortho;
        if (!ortho) {
            // The difference in double: a far eye and a small model lose no bits before rounding.
            v = glm::vec3(eye - pos[i]);
            const float len2 = glm::dot(v, v);
            v *= len2 > 0.0f ? 1.0f / std::sqrt(len2) : 0.0f;
        }
        view_curvature_at(normal[i], dir1[i], k1[i], k2[i], dcurv[i], v, ndotv[i], kr[i], dwkr[i]);
    }
}

}  // namespace inkline
