// Curvature lines of a triangle mesh (suggestive contours, smooth contours, ridges, valleys).
// Takes MeshTopology (positions, faces, edges) and a Camera; gives, once per model, per-vertex
// curvature (CurvatureField), per view the view-dependent quantities (ViewCurvature), and the
// curves that run across faces (SurfaceCurves). Built only when a requested line kind needs it.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "model/topology.hpp"

namespace inkline {

// Per vertex, structure of arrays, <= 64 bytes a vertex. Sign convention: curvature is positive
// where the surface bends away from its outward normal (a sphere with outward normals: k = +1/R).
struct CurvatureField {
    std::vector<glm::vec3> normal;  // unit; face normals weighted as in Max (1999)
    std::vector<glm::vec3> dir1;    // unit tangent direction of k1; dir2 = cross(normal, dir1)
    std::vector<float> k1, k2;      // principal curvatures, k1 >= k2
    // Derivative of the second fundamental form, C, in the (dir1, dir2) frame:
    // {C(d1,d1,d1), C(d1,d1,d2), C(d1,d2,d2), C(d2,d2,d2)} (Rusinkiewicz 2004).
    std::vector<std::array<float, 4>> dcurv;
    std::vector<float> point_area;  // Voronoi area (Meyer et al. 2003), the vertex's weight
    std::vector<std::uint8_t> valid;  // 0: could not be estimated here (isolated vertex, fewer than
                                      // two non-degenerate faces); its k1, k2, dcurv are 0 (normal
                                      // and dir1 kept where it has faces, else 0)
    std::size_t invalid_vertices = 0;
    // Length scale that makes thresholds dimensionless (scaling the model does not change the
    // drawing): the median edge length.
    double feature_size = 0.0;
    std::size_t size() const { return k1.size(); }
};

// Rusinkiewicz's per-face least-squares estimator, weighted to vertices by Voronoi area.
CurvatureField estimate_curvature(const MeshTopology& mesh);

// Per vertex, per view. v: unit vector from the vertex to the eye (orthographic: toward the eye
// along the view direction); w: v projected onto the tangent plane.
struct ViewCurvature {
    std::vector<float> ndotv;  // n . v
    std::vector<float> kr;     // radial curvature k1 cos^2(phi) + k2 sin^2(phi), phi from dir1 to w
                               // (may be scaled by a positive factor, e.g. |w|^2: same zero set)
    std::vector<float> dwkr;   // derivative of kr along w (same positive scaling convention as
                               // documented in the .cpp), the suggestive contours' side test
};
// Storage of `out` is reused from view to view.
void compute_view_curvature(const CurvatureField& field, const MeshTopology& mesh, const Camera& camera,
                            ViewCurvature& out);

// The same quantities at one vertex (view_curvature.cpp gives the formulas): from its unit normal,
// first principal direction, curvatures and C, and v (unit, toward the eye). Inline: the
// multi-scale detail evaluates it per vertex for two levels of smoothing (detail/).
inline void view_curvature_at(const glm::vec3& nrm, const glm::vec3& d1, float k1, float k2,
                              const std::array<float, 4>& C, const glm::vec3& v, float& ndotv, float& kr,
                              float& dwkr) {
    // Below this sin^2(theta) the view is head-on at the vertex: w has no direction, kr and D_w kr
    // are 0 there (their limits times sin), and the clamp only keeps the division finite.
    constexpr float kMinSin2 = 1e-12f;
    const glm::vec3 d2 = glm::cross(nrm, d1);
    const float nv = glm::dot(nrm, v);
    const float u = glm::dot(v, d1), t = glm::dot(v, d2);
    const float u2 = u * u, t2 = t * t;
    const float inv_sin2 = 1.0f / std::max(u2 + t2, kMinSin2);
    // C(w,w,w) / sin^2 = sin * C(w^,w^,w^); tau, the geodesic torsion along w^, times sin^2 / sin^2.
    const float cwww = (u2 * (u * C[0] + 3.0f * t * C[1]) + t2 * (3.0f * u * C[2] + t * C[3])) * inv_sin2;
    const float tau = (k2 - k1) * u * t * inv_sin2;
    ndotv = nv;
    kr = k1 * u2 + k2 * t2;
    dwkr = cwww - 2.0f * nv * tau * tau;
}

// Curves across faces: each a polyline whose points lie on mesh edges (or vertices), every
// segment inside one face. Points of neighbouring faces on a shared edge are identical (computed
// from the edge's two vertex values only), so chains join exactly.
struct SurfaceCurves {
    struct Curve {
        LineKind kind;
        std::uint32_t begin, end;  // points [begin, end)
        bool closed;               // last point == first point
    };
    std::vector<Curve> curves;
    std::vector<glm::dvec3> points;           // world positions
    std::vector<std::uint32_t> point_edge;    // the mesh edge each point lies on (at a vertex: one
                                              // of its edges; UINT32_MAX: inside a face, where a
                                              // test cut the curve)
    std::vector<std::uint32_t> segment_face;  // face of the segment from point i to i+1
                                              // (parallel to points; UINT32_MAX at a curve's last point)
    std::vector<float> strength;              // per point in [0, 1]: how far the line passes its
                                              // test (1: well above the threshold), for fading
    void clear();
};

struct SurfaceLineOptions {
    bool suggestive = true, smooth_contour = false, ridge = false, valley = false;
    // Thresholds are made dimensionless with rtsc's feature size (surface_lines.cpp says why not
    // CurvatureField::feature_size), and default to rtsc's values.
    // Suggestive contours: Dw kr / n.v above threshold / feature_size^2 (both tests of DeCarlo
    // et al. 2004 in one, as in rtsc).
    double suggestive_threshold = 0.01;
    double suggestive_max_ndotv = 1.0;   // (if used) reject where the view is nearly head-on
    // Ridges and valleys: principal curvature magnitude above threshold / feature_size.
    double ridge_threshold = 0.1;
};

// Extracts the requested curves for one view; `out` is overwritten (storage reused).
void extract_surface_lines(const MeshTopology& mesh, const CurvatureField& field, const ViewCurvature& view,
                           const Camera& camera, const SurfaceLineOptions& options, SurfaceCurves& out);

}  // namespace inkline
