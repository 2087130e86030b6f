// The tests' sample models and standard cameras, named once. Needs INKLINE_DATA_DIR from CMake
// (the folder holding meshes/: Debian's libcgal-demo models).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <string>

#include <glm/geometric.hpp>

#include "core/camera.hpp"
#include "core/drawing.hpp"
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
// The box around a mesh's vertices.
inline Bounds3 bounds_of(const TriangleMesh& m) {
    Bounds3 b{m.positions[0], m.positions[0]};
    for (const auto& p : m.positions) {
        b.lo = glm::min(b.lo, p);
        b.hi = glm::max(b.hi, p);
    }
    return b;
}

// V - E + F of the faces' vertices and edges.
inline long euler_characteristic(const TriangleMesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++edges[std::minmax(t[k], t[(k + 1) % 3])];
    return long(m.positions.size()) - long(edges.size()) + long(m.triangles.size());
}

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


// Visible line length of a drawing, in pixels.
inline double visible_length_px(const Drawing& d) {
    double sum = 0.0;
    for (const Piece& p : d.pieces)
        if (p.qi == 0)
            for (std::size_t i = 1; i < p.points.size(); ++i) sum += glm::length(p.points[i] - p.points[i - 1]);
    return sum;
}

// Issue 43's measure of detail along a dolly from `framed` to 8x farther (same target and up):
// visible line length (`plain`, `detail`: a drawing's at a camera) per unit of the model's image
// disc. A fixed drawing's density grows about 8x (an outline shrinks like 1/d, the disc like 1/d^2).
struct DollyDensity {
    double plain_start = 0.0, detail_start = 0.0;    // lengths at the start, px
    double plain_growth = 0.0, detail_growth = 0.0;  // density at 8x over density at 1x
};
inline DollyDensity dolly_density(const Bounds3& bounds, const Camera& framed,
                                  const std::function<double(const Camera&)>& plain,
                                  const std::function<double(const Camera&)>& detail) {
    const glm::dvec3 c = bounds.center(), offset = framed.eye() - c;
    DollyDensity r;
    double plain_density = 0.0, detail_density = 0.0;  // at the start
    for (double factor : {1.0, 8.0}) {
        const Camera cam = Camera::perspective(c + factor * offset, c, {0, 1, 0}, 30.0, framed.width(), framed.height());
        const double radius_px = bounds.half_diagonal() * cam.focal() / (factor * glm::length(offset));
        const double area = M_PI * radius_px * radius_px;
        const double lp = plain(cam), ld = detail(cam);
        if (factor == 1.0) {
            r.plain_start = lp, r.detail_start = ld;
            plain_density = lp / area, detail_density = ld / area;
        } else {
            r.plain_growth = (lp / area) / plain_density, r.detail_growth = (ld / area) / detail_density;
        }
    }
    return r;
}
}  // namespace inkline::test
