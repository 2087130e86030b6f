// Uniform point coverage and stroke growth (Elber 99, section 2.1, after Elber 98 [8]).
// Takes surfaces; gives r points spread with density proportional to the area element
// |S_u x S_v| (stratified over a parameter grid, deterministic seed), and a stroke grown from each
// by numerical marching in the parameter domain (so every stroke point is exactly on the surface):
// adaptive midpoint (RK2) steps of at most `max_turn` radians of normal curvature, stopping at a
// patch boundary (periodic directions wrap), at the length limit, or where the direction field is
// undefined (degenerate normal, umbilic for lines of curvature, zero gradient for isophotes).
// Each stroke keeps its seed point, unit normal N_i there and arc length s_i.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "freeform/surface.hpp"

namespace inkline::freeform {

struct SurfaceSample {
    std::uint32_t surface = 0;
    glm::dvec2 uv{0.0};
};

// r points over all surfaces together, density proportional to area. `cells` x `cells` strata per
// surface; each stratum receives its expected share of points, the fractional part by a coin.
std::vector<SurfaceSample> cover(const SurfaceList& surfaces, std::size_t r, std::uint64_t seed, int cells = 24);
// Total area by the same quadrature as cover() (used by tests).
double total_area(const SurfaceList& surfaces, int cells = 24);

enum class StrokeField {
    IsoU,          // u constant: marching along v
    IsoV,          // v constant: marching along u
    Iso,           // IsoV for even seeds, IsoU for odd
    CurvatureMax,  // line of curvature along the principal direction of k1
    CurvatureMin,  // ... of k2
    Curvature,     // k1 direction for even seeds, k2 for odd
    Isophote,      // constant angle between N and a fixed direction: the paper's "silhouette lines"
    Direction,     // a prescribed field: `direction` projected onto the tangent plane
};
// "iso", "iso-u", "iso-v", "curvature", "curvature-max", "curvature-min", "isophote", "direction".
bool parse_stroke_field(const std::string& s, StrokeField& out);

struct StrokeOptions {
    StrokeField field = StrokeField::Iso;
    double length = 0.1;                  // world arc length limit (half each way from the seed)
    double max_turn = 0.08;               // radians of turning per step (curvature-adaptive step)
    double min_step_fraction = 1.0 / 64;  // of `length`
    glm::dvec3 isophote_direction{0, 0, 1};
    glm::dvec3 direction{1, 0, 0};  // the prescribed field of StrokeField::Direction
};

struct Stroke {
    std::uint32_t surface = 0;
    glm::dvec2 seed_uv{0.0};
    glm::dvec3 seed{0.0}, normal{0.0};  // P_i and N_i
    std::vector<glm::dvec3> points;     // from one end to the other, through the seed
    std::vector<glm::dvec2> uv;         // parameters of the points (wrapped into the domain)
    std::vector<double> arc;            // cumulative arc length, arc.front() = 0
    std::size_t seed_at = 0;            // index of the seed in points
    double length() const { return arc.empty() ? 0.0 : arc.back(); }
};

// For polygonal surfaces (the paper, section 2.1): r points, each triangle receiving r * area / total
// (the fraction by a coin), uniform inside it. Deterministic for a seed.
struct MeshSample {
    std::uint32_t face = 0;
    glm::dvec3 point{0.0};
};
std::vector<MeshSample> cover_mesh(const std::vector<glm::dvec3>& positions,
                                   const std::vector<std::array<std::uint32_t, 3>>& triangles, std::size_t r,
                                   std::uint64_t seed);

Stroke grow_stroke(const Surface& s, std::uint32_t surface_index, glm::dvec2 uv, StrokeField field,
                   const StrokeOptions& options);
// One stroke per sample (the field alternates by sample index for Iso and Curvature); strokes with
// an undefined normal at the seed are skipped. Deterministic.
std::vector<Stroke> grow_strokes(const SurfaceList& surfaces, const std::vector<SurfaceSample>& samples,
                                 const StrokeOptions& options);

}  // namespace inkline::freeform
