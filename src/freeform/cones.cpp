#include "freeform/cones.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <map>
#include <mutex>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <glm/geometric.hpp>

namespace inkline::freeform {
namespace {

double angle(const glm::dvec3& a, const glm::dvec3& b) { return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)); }

// Slack on angles in the culling tests: rounding of acos and dot products, never a visible change.
constexpr double kAngleSlack = 1e-9;

}  // namespace

std::vector<glm::dvec3> fibonacci_sphere(int m) {
    std::vector<glm::dvec3> p;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < m; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / m;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        p.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
    }
    return p;
}

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// Delaunay triangles of unit vectors (the facets of their convex hull), as indices.
std::vector<std::array<std::uint32_t, 3>> spherical_delaunay(const std::vector<glm::dvec3>& x) {
    std::vector<Kernel::Point_3> pts;
    std::map<std::array<double, 3>, std::uint32_t> index;
    for (std::uint32_t i = 0; i < x.size(); ++i) {
        pts.emplace_back(x[i].x, x[i].y, x[i].z);
        index[{x[i].x, x[i].y, x[i].z}] = i;
    }
    CGAL::Surface_mesh<Kernel::Point_3> hull;
    CGAL::convex_hull_3(pts.begin(), pts.end(), hull);
    std::vector<std::array<std::uint32_t, 3>> out;
    for (auto f : hull.faces()) {
        std::array<std::uint32_t, 3> t{};
        int k = 0;
        for (auto v : CGAL::vertices_around_face(hull.halfedge(f), hull)) {
            const auto& p = hull.point(v);
            if (k < 3) t[std::size_t(k)] = index.at({p.x(), p.y(), p.z()});
            ++k;
        }
        if (k == 3) out.push_back(t);
    }
    return out;
}

// Circumcentre (the Voronoi vertex) and angular circumradius of each Delaunay triangle.
double hull_covering(const std::vector<glm::dvec3>& x, const std::vector<std::array<std::uint32_t, 3>>& tris,
                     std::vector<glm::dvec3>& centres, std::vector<double>& radii) {
    double worst = 0.0;
    centres.clear();
    radii.clear();
    for (const auto& t : tris) {
        glm::dvec3 q = glm::normalize(glm::cross(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]));
        if (glm::dot(q, x[t[0]]) < 0.0) q = -q;
        const double r = angle(q, x[t[0]]);
        worst = std::max(worst, r);
        centres.push_back(q);
        radii.push_back(r);
    }
    return worst;
}

// Lowers the covering angle: the vertices of the Delaunay triangles with the largest circumradii
// are pushed towards those triangles' circumcentres (the holes of the covering), with a decaying
// step; the best configuration seen is kept.
std::vector<glm::dvec3> push_into_holes(std::vector<glm::dvec3> x, int iterations) {
    std::vector<glm::dvec3> best = x, centres, move(x.size());
    std::vector<double> radii;
    double best_angle = 1e9, eta = 0.2;
    for (int k = 0; k < iterations; ++k) {
        const auto tris = spherical_delaunay(x);
        const double a = hull_covering(x, tris, centres, radii);
        if (a < best_angle) best_angle = a, best = x;
        std::fill(move.begin(), move.end(), glm::dvec3(0.0));
        for (std::size_t f = 0; f < tris.size(); ++f) {
            const double w = std::max(0.0, (radii[f] - 0.9 * a) / (0.1 * a));
            if (w <= 0.0) continue;
            for (std::uint32_t i : tris[f]) move[i] += w * w * (centres[f] - x[i]);
        }
        for (std::size_t i = 0; i < x.size(); ++i) x[i] = glm::normalize(x[i] + eta * move[i]);
        eta *= 0.995;
    }
    return best;
}

std::vector<glm::dvec3> riesz(std::vector<glm::dvec3> x, int iterations) {
    const std::size_t m = x.size();
    std::vector<glm::dvec3> f(m);
    double step = 0.5 / std::sqrt(double(m));
    for (int it = 0; it < iterations; ++it) {
        for (std::size_t i = 0; i < m; ++i) {
            glm::dvec3 F(0.0);
            for (std::size_t j = 0; j < m; ++j) {
                if (j == i) continue;
                const glm::dvec3 d = x[i] - x[j];
                const double l = glm::length(d);
                F += d / (l * l * l);
            }
            f[i] = F - x[i] * glm::dot(F, x[i]);
        }
        double fmax = 0.0;
        for (const auto& F : f) fmax = std::max(fmax, glm::length(F));
        if (!(fmax > 0.0)) break;
        for (std::size_t i = 0; i < m; ++i) x[i] = glm::normalize(x[i] + (step / fmax) * f[i]);
        step *= 0.992;
    }
    return x;
}

}  // namespace

std::vector<glm::dvec3> optimize_cone_axes(int m) {
    std::vector<glm::dvec3> x = fibonacci_sphere(m);
    if (m >= 4 && m <= kMaxOptimizedCones) {
        x = riesz(x, 400);
        x = push_into_holes(x, 1500);
    }
    return x;
}

std::vector<glm::dvec3> cone_axes(int m) {
    static std::mutex mutex;
    static std::map<int, std::vector<glm::dvec3>> cache;  // deterministic: computed once per m
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (auto it = cache.find(m); it != cache.end()) return it->second;
    }
    std::vector<glm::dvec3> x = optimize_cone_axes(m);
    std::lock_guard<std::mutex> lock(mutex);
    cache[m] = x;
    return x;
}

double hull_covering_angle(const std::vector<glm::dvec3>& axes) {
    if (axes.size() < 4) return M_PI;
    std::vector<glm::dvec3> centres;
    std::vector<double> radii;
    return hull_covering(axes, spherical_delaunay(axes), centres, radii);
}

double covering_angle(const std::vector<glm::dvec3>& axes, int samples) {
    if (axes.empty()) return M_PI;
    if (axes.size() < 3) {  // no Voronoi vertices: the far side of the nearest axis decides
        double worst = 0.0;
        for (const glm::dvec3& s : fibonacci_sphere(samples)) {
            double best = -1.0;
            for (const auto& a : axes) best = std::max(best, glm::dot(s, a));
            worst = std::max(worst, std::acos(std::clamp(best, -1.0, 1.0)));
        }
        return worst;
    }
    const std::vector<glm::dvec3> dirs = fibonacci_sphere(samples);
    std::vector<double> nearest(dirs.size());
    double sampled = 0.0;
    for (std::size_t k = 0; k < dirs.size(); ++k) {
        double best = -2.0;
        for (const auto& a : axes) best = std::max(best, glm::dot(dirs[k], a));
        nearest[k] = std::acos(std::clamp(best, -1.0, 1.0));
        sampled = std::max(sampled, nearest[k]);
    }
    const double spacing = std::sqrt(4.0 * M_PI / samples);
    double exact = sampled;
    std::vector<std::array<std::uint32_t, 3>> seen;
    for (std::size_t k = 0; k < dirs.size(); ++k) {
        if (nearest[k] < sampled - 4.0 * spacing) continue;
        // Three nearest axes.
        std::array<std::pair<double, std::uint32_t>, 3> top{{{-3, 0}, {-3, 0}, {-3, 0}}};
        for (std::uint32_t l = 0; l < axes.size(); ++l) {
            const double d = glm::dot(dirs[k], axes[l]);
            if (d > top[2].first) {
                top[2] = {d, l};
                std::sort(top.begin(), top.end(), std::greater<>());
            }
        }
        std::array<std::uint32_t, 3> tri{top[0].second, top[1].second, top[2].second};
        std::sort(tri.begin(), tri.end());
        if (std::find(seen.begin(), seen.end(), tri) != seen.end()) continue;
        seen.push_back(tri);
        const glm::dvec3 &a = axes[tri[0]], &b = axes[tri[1]], &c = axes[tri[2]];
        glm::dvec3 q = glm::cross(b - a, c - a);
        const double ql = glm::length(q);
        if (!(ql > 1e-15)) continue;
        q /= ql;
        if (glm::dot(q, dirs[k]) < 0.0) q = -q;
        const double da = glm::dot(q, a);
        double best = -2.0;
        for (const auto& x : axes) best = std::max(best, glm::dot(q, x));
        if (best > da + 1e-12) continue;  // another axis is nearer: not a Voronoi vertex
        exact = std::max(exact, std::acos(std::clamp(da, -1.0, 1.0)));
    }
    return exact;
}

bool parse_shader(const std::string& s, ShaderKind& out) {
    if (s == "diffuse") return out = ShaderKind::Diffuse, true;
    if (s == "silhouette") return out = ShaderKind::Silhouette, true;
    if (s == "combined") return out = ShaderKind::Combined, true;
    return false;
}

double Shader::diffuse(const glm::dvec3& n) const {
    if (lights.empty()) return 0.0;
    double sum = 0.0;
    for (const auto& l : lights) sum += std::pow(std::max(glm::dot(n, l), 0.0), c);
    return std::max(sum / double(lights.size()) - tau_dif, 0.0);
}

double Shader::silhouette(const glm::dvec3& n, const glm::dvec3& v) const {
    return std::max(std::pow(1.0 - std::min(1.0, std::abs(glm::dot(n, v))), d) - tau_sil, 0.0);
}

double Shader::operator()(const glm::dvec3& n, const glm::dvec3& v) const {
    switch (kind) {
        case ShaderKind::Diffuse: return diffuse(n);
        case ShaderKind::Silhouette: return silhouette(n, v);
        case ShaderKind::Combined: return 0.5 * (diffuse(n) + silhouette(n, v));
    }
    return 0.0;
}

double Shader::best_case(const glm::dvec3& axis, double radius, const glm::dvec3& v, double beta) const {
    const double r = radius + kAngleSlack;
    double dif = 0.0;
    if (kind != ShaderKind::Silhouette && !lights.empty()) {
        double sum = 0.0;
        for (const auto& l : lights) sum += std::pow(std::max(std::cos(std::max(0.0, angle(axis, l) - r)), 0.0), c);
        dif = std::max(sum / double(lights.size()) - tau_dif, 0.0);
    }
    double sil = 0.0;
    if (kind != ShaderKind::Diffuse) {
        const double th = angle(axis, v), rho = r + beta;
        const double lo = std::max(0.0, th - rho), hi = std::min(M_PI, th + rho);
        const double min_abs_cos = lo <= M_PI / 2 && hi >= M_PI / 2 ? 0.0 : std::min(std::abs(std::cos(lo)), std::abs(std::cos(hi)));
        sil = std::max(std::pow(1.0 - min_abs_cos, d) - tau_sil, 0.0);
    }
    switch (kind) {
        case ShaderKind::Diffuse: return dif;
        case ShaderKind::Silhouette: return sil;
        case ShaderKind::Combined: return 0.5 * (dif + sil);
    }
    return 0.0;
}

ViewQuery make_query(const glm::dvec3& eye, const glm::dvec3& forward, bool ortho, const glm::dvec3& center,
                     double radius, bool closed) {
    ViewQuery q;
    q.eye = eye;
    q.ortho = ortho;
    q.closed = closed;
    if (ortho) {
        q.view = -glm::normalize(forward);
        q.beta = 0.0;
    } else {
        const glm::dvec3 d = eye - center;
        const double D = glm::length(d);
        q.view = D > 0.0 ? d / D : -glm::normalize(forward);
        q.beta = D > radius ? std::asin(std::min(1.0, radius / D)) : M_PI;
    }
    return q;
}

namespace {
bool shade_stroke(const glm::dvec3& n, const glm::dvec3& seed, const ViewQuery& q, const Shader& shader, double& psi) {
    const glm::dvec3 v = q.ortho ? q.view : glm::normalize(q.eye - seed);
    if (q.closed && glm::dot(n, v) < 0.0) return false;
    psi = shader(n, v);
    return psi > 0.0;
}
}  // namespace

ConeBuckets::ConeBuckets(std::vector<glm::dvec3> axes, double alpha, const std::vector<glm::dvec3>& normals,
                         const std::vector<glm::dvec3>& seeds, BucketMode mode)
    : axes_(std::move(axes)), alpha_(alpha), buckets_(axes_.size()), radius_(axes_.size(), 0.0), normals_(normals),
      seeds_(seeds), mark_(normals.size(), 0) {
    const double cos_a = std::cos(alpha_);
    for (std::uint32_t i = 0; i < normals_.size(); ++i) {
        const glm::dvec3& n = normals_[i];
        std::size_t nearest = 0;
        double best = -2.0;
        bool placed = false;
        for (std::size_t l = 0; l < axes_.size(); ++l) {
            const double d = glm::dot(n, axes_[l]);
            if (d > best) best = d, nearest = l;
            if (mode == BucketMode::Redundant && d >= cos_a) {
                buckets_[l].push_back(i);
                radius_[l] = std::max(radius_[l], angle(n, axes_[l]));
                placed = true;
            }
        }
        if (!placed) {  // exclusive mode, or a normal the (sampled) covering angle just misses
            buckets_[nearest].push_back(i);
            radius_[nearest] = std::max(radius_[nearest], angle(n, axes_[nearest]));
        }
    }
}

std::size_t ConeBuckets::entries() const {
    std::size_t n = 0;
    for (const auto& b : buckets_) n += b.size();
    return n;
}

std::vector<Selected> ConeBuckets::select(const ViewQuery& q, const Shader& shader, bool cull, SelectStats* stats) {
    if (++frame_ == 0) {  // wrapped: reset the marks
        std::fill(mark_.begin(), mark_.end(), 0u);
        frame_ = 1;
    }
    SelectStats st;
    std::vector<Selected> out;
    for (std::size_t l = 0; l < axes_.size(); ++l) {
        if (buckets_[l].empty()) continue;
        if (cull) {
            const double rho = radius_[l] + q.beta + kAngleSlack;
            if (q.closed && angle(axes_[l], q.view) - rho > M_PI / 2) {  // V_l . V < -sin(alpha + beta)
                ++st.cones_culled_back;
                continue;
            }
            if (!(shader.best_case(axes_[l], radius_[l], q.view, q.beta) > 0.0)) {
                ++st.cones_culled_shader;
                continue;
            }
        }
        ++st.cones_visited;
        for (std::uint32_t i : buckets_[l]) {
            if (mark_[i] == frame_) {
                ++st.duplicates_skipped;
                continue;
            }
            mark_[i] = frame_;
            ++st.strokes_tested;
            double psi = 0.0;
            if (shade_stroke(normals_[i], seeds_[i], q, shader, psi)) out.push_back({i, psi});
        }
    }
    if (stats) *stats = st;
    return out;
}

std::vector<Selected> select_all(const std::vector<glm::dvec3>& normals, const std::vector<glm::dvec3>& seeds,
                                 const ViewQuery& q, const Shader& shader) {
    std::vector<Selected> out;
    for (std::uint32_t i = 0; i < normals.size(); ++i) {
        double psi = 0.0;
        if (shade_stroke(normals[i], seeds[i], q, shader, psi)) out.push_back({i, psi});
    }
    return out;
}

}  // namespace inkline::freeform
