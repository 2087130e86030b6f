// Gauss-map cone buckets and shaders (Elber 99, sections 2.2 and 2.3).
// Takes strokes (their unit normals N_i) and per view a viewing direction, lights and a shader;
// gives the strokes to draw with their shader value psi_i, touching only the buckets of cones that
// can contribute. A brute-force scan of every stroke (select_all) is the exact reference beside it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace inkline::freeform {

// m near-uniform unit vectors for the cones: a Fibonacci spiral, spread by minimising the Riesz
// s = 1 energy (repulsion), then the covering angle lowered directly: the vertices of the
// spherical Delaunay triangles (CGAL convex hull) with the largest circumradii are pushed into
// those holes (1500 decaying steps, best kept). Beyond kMaxOptimizedCones: the spiral alone.
// Deterministic; cached per m.
inline constexpr int kMaxOptimizedCones = 2000;
std::vector<glm::dvec3> fibonacci_sphere(int m);
std::vector<glm::dvec3> cone_axes(int m);
std::vector<glm::dvec3> optimize_cone_axes(int m);  // the same, computed (not cached)
// The covering angle from the Delaunay triangles' circumradii (exact up to rounding, needs the
// axes not all in one hemisphere): a check on covering_angle below.
double hull_covering_angle(const std::vector<glm::dvec3>& axes);

// Covering angle (radians) of the axes: the maximum over the sphere of the angle to the nearest
// axis. Dense sampling (`samples` spiral directions) finds the regions of the maxima; the maximum
// is then located exactly at Voronoi vertices (points equidistant from their three nearest axes,
// with no axis closer) of the triples nearest to the far samples.
double covering_angle(const std::vector<glm::dvec3>& axes, int samples = 200000);

enum class BucketMode {
    Redundant,  // every cone with N_i . V_l >= cos(alpha_m) (the paper's equation 1)
    Exclusive,  // only the nearest cone (the paper's alternative: no duplicates, uneven buckets)
};

enum class ShaderKind { Diffuse, Silhouette, Combined };
bool parse_shader(const std::string& s, ShaderKind& out);  // "diffuse", "silhouette", "combined"

// Equations 4-6 as we read them (the equations are garbled in our copy of the paper):
//   psi_dif = max((1/n) sum_j max(N . L_j, 0)^c - tau_dif, 0)             (4)
//   psi_sil = max((1 - |N . V|)^d - tau_sil, 0)                            (5)
//   psi     = (psi_dif + psi_sil) / 2                                      (6)
// (psi in [0, 1]; V is the unit direction from the surface point to the eye.)
struct Shader {
    ShaderKind kind = ShaderKind::Combined;
    std::vector<glm::dvec3> lights{glm::dvec3(0.0, 0.0, 1.0)};  // unit directions towards the lights
    double c = 2.0, tau_dif = 0.1;
    double d = 2.0, tau_sil = 0.2;

    double diffuse(const glm::dvec3& n) const;
    double silhouette(const glm::dvec3& n, const glm::dvec3& v) const;
    double operator()(const glm::dvec3& n, const glm::dvec3& v) const;
    // Upper bound of the shader over all normals within `radius` of `axis` and view directions
    // within `beta` of `v` (angles in radians): zero means no stroke of the cone can show.
    double best_case(const glm::dvec3& axis, double radius, const glm::dvec3& v, double beta) const;
};

// Per-view query. Perspective: V_i = normalize(eye - P_i) varies over the object; `view` is the
// direction to the eye from `center` and `beta` bounds the angle between any V_i and `view`.
struct ViewQuery {
    glm::dvec3 eye{0.0};
    bool ortho = false;
    glm::dvec3 view{0.0, 0.0, 1.0};  // unit, towards the viewer
    double beta = 0.0;
    bool closed = false;  // closed object: back-facing strokes (N_i . V_i < 0) are never drawn
};
// The query for a camera and strokes whose seeds lie within `radius` of `center`.
ViewQuery make_query(const glm::dvec3& eye, const glm::dvec3& forward, bool ortho, const glm::dvec3& center,
                     double radius, bool closed);

struct Selected {
    std::uint32_t stroke;
    double psi;
};

struct SelectStats {
    std::size_t cones_visited = 0, cones_culled_back = 0, cones_culled_shader = 0;
    std::size_t strokes_tested = 0, duplicates_skipped = 0;
};

class ConeBuckets {
public:
    // alpha: covering angle of the axes (radians).
    ConeBuckets(std::vector<glm::dvec3> axes, double alpha, const std::vector<glm::dvec3>& normals,
                const std::vector<glm::dvec3>& seeds, BucketMode mode);

    const std::vector<glm::dvec3>& axes() const { return axes_; }
    double alpha() const { return alpha_; }
    const std::vector<std::uint32_t>& bucket(std::size_t l) const { return buckets_[l]; }
    // Largest angle between the axis and a normal in the bucket (<= alpha for Redundant).
    double radius(std::size_t l) const { return radius_[l]; }
    std::size_t entries() const;  // sum of bucket sizes (redundancy = entries / strokes)

    // Strokes with psi > 0 (and, on closed objects, facing the viewer), visiting only cones that
    // can contribute; `cull` false visits every cone (same answer, for comparison). Each stroke
    // is reported once per call (the per-frame magic number of Algorithm 1).
    std::vector<Selected> select(const ViewQuery& q, const Shader& shader, bool cull = true,
                                 SelectStats* stats = nullptr);

private:
    std::vector<glm::dvec3> axes_;
    double alpha_;
    std::vector<std::vector<std::uint32_t>> buckets_;
    std::vector<double> radius_;
    std::vector<glm::dvec3> normals_, seeds_;
    std::vector<std::uint32_t> mark_;  // per stroke: the frame that drew it last
    std::uint32_t frame_ = 0;
};

// The exact reference: every stroke scanned.
std::vector<Selected> select_all(const std::vector<glm::dvec3>& normals, const std::vector<glm::dvec3>& seeds,
                                 const ViewQuery& q, const Shader& shader);

}  // namespace inkline::freeform
