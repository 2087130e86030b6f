#include "freeform/strokes.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <glm/geometric.hpp>

namespace inkline::freeform {
namespace {

double area_element(const Surface& s, double u, double v) {
    const SurfacePoint p = s.eval(u, v);
    return glm::length(glm::cross(p.su, p.sv));
}

// Gauss-Legendre 2x2 area of a parameter cell, and a bound on the area element in it.
struct CellArea {
    double area = 0.0, max_element = 0.0;
};
CellArea cell_area(const Surface& s, double u0, double u1, double v0, double v1) {
    static const double g[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
    CellArea c;
    const double du = u1 - u0, dv = v1 - v0;
    for (double a : g)
        for (double b : g) {
            const double e = area_element(s, u0 + a * du, v0 + b * dv);
            c.area += 0.25 * e * du * dv;
            c.max_element = std::max(c.max_element, e);
        }
    for (double a : {0.0, 0.5, 1.0})
        for (double b : {0.0, 0.5, 1.0}) c.max_element = std::max(c.max_element, area_element(s, u0 + a * du, v0 + b * dv));
    c.max_element *= 1.25;  // margin: rejection sampling below needs an upper bound
    return c;
}

glm::dvec3 normal_derivative(const glm::dvec3& cd, double len, const glm::dvec3& n) {
    return (cd - n * glm::dot(n, cd)) / len;
}

// Unit tangent direction of the field at uv, as a parameter-space vector d with |S_u d.x + S_v d.y| = 1,
// turned to agree with `prev` (zero vector: no preference). False where the field is undefined.
bool field_direction(const Surface& s, glm::dvec2 uv, StrokeField f, const StrokeOptions& o, const glm::dvec3& prev,
                     glm::dvec2& d, glm::dvec3& T, double& kmax) {
    const glm::dvec3& iso_dir = o.isophote_direction;
    const SurfacePoint p = s.eval(uv.x, uv.y);
    const Curvature c = curvature_of(p, s.sign);
    if (!c.valid) return false;
    kmax = std::max(std::abs(c.k1), std::abs(c.k2));
    switch (f) {
        case StrokeField::IsoU: d = {0.0, 1.0}; break;
        case StrokeField::IsoV: d = {1.0, 0.0}; break;
        case StrokeField::CurvatureMax:
        case StrokeField::CurvatureMin: {
            const double gap = std::abs(c.k1 - c.k2);
            if (gap <= 1e-6 * (kmax + 1e-12) || gap < 1e-9) return false;  // umbilic
            d = f == StrokeField::CurvatureMax ? c.uv1 : c.uv2;
            break;
        }
        case StrokeField::Isophote: {
            const glm::dvec3 cr = glm::cross(p.su, p.sv);
            const double len = glm::length(cr);
            const glm::dvec3 nu = normal_derivative(glm::cross(p.suu, p.sv) + glm::cross(p.su, p.suv), len, c.n * s.sign);
            const glm::dvec3 nv = normal_derivative(glm::cross(p.suv, p.sv) + glm::cross(p.su, p.svv), len, c.n * s.sign);
            const glm::dvec2 g(glm::dot(nu, iso_dir), glm::dot(nv, iso_dir));
            d = {-g.y, g.x};
            break;
        }
        case StrokeField::Direction: {
            const glm::dvec3 t = o.direction - c.n * glm::dot(c.n, o.direction);  // onto the tangent plane
            const double E = glm::dot(p.su, p.su), F = glm::dot(p.su, p.sv), G = glm::dot(p.sv, p.sv);
            const double det = E * G - F * F, a1 = glm::dot(p.su, t), a2 = glm::dot(p.sv, t);
            d = {(G * a1 - F * a2) / det, (E * a2 - F * a1) / det};
            break;
        }
        default: return false;
    }
    T = d.x * p.su + d.y * p.sv;
    const double l = glm::length(T);
    if (!(l > 1e-12)) return false;
    d /= l;
    T /= l;
    if (glm::dot(T, prev) < 0.0) d = -d, T = -T;
    return true;
}

// Wraps periodic coordinates into the domain; false when a non-periodic one left it.
bool inside(const Surface& s, glm::dvec2& uv) {
    auto fix = [](double& x, const glm::dvec2& r, bool periodic) {
        if (periodic) {
            const double w = r[1] - r[0];
            x = r[0] + std::fmod(std::fmod(x - r[0], w) + w, w);
            return true;
        }
        return x >= r[0] && x <= r[1];
    };
    const bool a = fix(uv.x, s.u_range, s.periodic_u);
    const bool b = fix(uv.y, s.v_range, s.periodic_v);
    return a && b;
}

// Largest t in (0, 1] with uv + t * step inside the non-periodic ranges.
double boundary_fraction(const Surface& s, glm::dvec2 uv, glm::dvec2 step) {
    double t = 1.0;
    auto lim = [&](double x, double dx, const glm::dvec2& r, bool periodic) {
        if (periodic || dx == 0.0) return;
        if (x + dx > r[1]) t = std::min(t, (r[1] - x) / dx);
        if (x + dx < r[0]) t = std::min(t, (r[0] - x) / dx);
    };
    lim(uv.x, step.x, s.u_range, s.periodic_u);
    lim(uv.y, step.y, s.v_range, s.periodic_v);
    return std::max(0.0, t);
}

// March from uv in direction sense (+1 / -1) up to `budget` arc length. Appends points (excluding uv).
void march(const Surface& s, glm::dvec2 uv, StrokeField f, const StrokeOptions& o, glm::dvec3 dir0, double budget,
           std::vector<glm::dvec3>& pts, std::vector<glm::dvec2>& uvs) {
    glm::dvec3 P = s.eval(uv.x, uv.y).p, prev = dir0;
    double done = 0.0;
    const double hmin = o.length * o.min_step_fraction, hmax = o.length / 6.0;
    for (int guard = 0; guard < 10000 && done < budget; ++guard) {
        glm::dvec2 d1, d2;
        glm::dvec3 T1, T2;
        double k1 = 0, k2 = 0;
        if (!field_direction(s, uv, f, o, prev, d1, T1, k1)) return;
        if (glm::dot(T1, prev) < 0.5) return;  // the field turned sharply: a singularity
        double h = std::clamp(o.max_turn / std::max(k1, 1e-12), hmin, hmax);
        h = std::min(h, budget - done);
        glm::dvec2 mid = uv + 0.5 * h * d1;
        const bool mid_in = inside(s, mid);
        if (!mid_in || !field_direction(s, mid, f, o, T1, d2, T2, k2)) d2 = d1, T2 = T1;
        glm::dvec2 step = h * d2;
        const double t = boundary_fraction(s, uv, step);
        const bool last = t < 1.0;
        glm::dvec2 next = uv + t * step;
        if (!inside(s, next)) return;
        glm::dvec3 Q = s.eval(next.x, next.y).p;
        double chord = glm::length(Q - P);
        // The chord of a step is not exactly h: shorten the last one to end at the length limit.
        bool at_limit = false;
        for (int fix = 0; fix < 4 && done + chord > budget && chord > 0.0; ++fix) {
            at_limit = true;
            const double scale = (budget - done) / chord;
            const double t2 = t * scale * (1.0 - 1e-12);
            next = uv + t2 * step;
            if (!inside(s, next)) return;
            Q = s.eval(next.x, next.y).p;
            chord = glm::length(Q - P);
        }
        if (done + chord > budget * (1.0 + 1e-9)) return;
        if (!(chord > 0.0)) return;
        pts.push_back(Q);
        uvs.push_back(next);
        done += chord;
        prev = T2;
        P = Q;
        uv = next;
        if (last || at_limit) return;  // reached the patch boundary or the length limit
    }
}

}  // namespace

bool parse_stroke_field(const std::string& s, StrokeField& out) {
    static const std::pair<const char*, StrokeField> names[] = {
        {"iso", StrokeField::Iso},           {"iso-u", StrokeField::IsoU},
        {"iso-v", StrokeField::IsoV},        {"curvature", StrokeField::Curvature},
        {"curvature-max", StrokeField::CurvatureMax}, {"curvature-min", StrokeField::CurvatureMin},
        {"isophote", StrokeField::Isophote}, {"direction", StrokeField::Direction}};
    for (const auto& [n, f] : names)
        if (s == n) return out = f, true;
    return false;
}

double total_area(const SurfaceList& surfaces, int cells) {
    double a = 0.0;
    for (const auto& sp : surfaces) {
        const Surface& s = *sp;
        const double du = (s.u_range[1] - s.u_range[0]) / cells, dv = (s.v_range[1] - s.v_range[0]) / cells;
        for (int i = 0; i < cells; ++i)
            for (int j = 0; j < cells; ++j)
                a += cell_area(s, s.u_range[0] + i * du, s.u_range[0] + (i + 1) * du, s.v_range[0] + j * dv,
                               s.v_range[0] + (j + 1) * dv).area;
    }
    return a;
}

std::vector<SurfaceSample> cover(const SurfaceList& surfaces, std::size_t r, std::uint64_t seed, int cells) {
    struct Cell {
        std::uint32_t s;
        double u0, u1, v0, v1;
        CellArea a;
    };
    std::vector<Cell> all;
    double total = 0.0;
    for (std::uint32_t k = 0; k < surfaces.size(); ++k) {
        const Surface& s = *surfaces[k];
        const double du = (s.u_range[1] - s.u_range[0]) / cells, dv = (s.v_range[1] - s.v_range[0]) / cells;
        for (int i = 0; i < cells; ++i)
            for (int j = 0; j < cells; ++j) {
                Cell c{k, s.u_range[0] + i * du, s.u_range[0] + (i + 1) * du, s.v_range[0] + j * dv,
                       s.v_range[0] + (j + 1) * dv, {}};
                c.a = cell_area(s, c.u0, c.u1, c.v0, c.v1);
                total += c.a.area;
                all.push_back(c);
            }
    }
    std::vector<SurfaceSample> out;
    // An infinite total (a surface of coordinates near 1e300) would make every share NaN.
    if (!(total > 0.0) || !std::isfinite(total) || r == 0) return out;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    out.reserve(r + all.size());
    for (const Cell& c : all) {
        const double expected = double(r) * c.a.area / total;
        std::size_t n = std::size_t(expected);
        if (U(rng) < expected - double(n)) ++n;  // fractional placement
        const Surface& s = *surfaces[c.s];
        for (std::size_t q = 0; q < n; ++q) {
            // Rejection against the area element: exact density |S_u x S_v| inside the stratum.
            for (int tries = 0; tries < 1000; ++tries) {
                const double u = c.u0 + U(rng) * (c.u1 - c.u0), v = c.v0 + U(rng) * (c.v1 - c.v0);
                if (U(rng) * c.a.max_element <= area_element(s, u, v)) {
                    out.push_back({c.s, {u, v}});
                    break;
                }
            }
        }
    }
    return out;
}

std::vector<MeshSample> cover_mesh(const std::vector<glm::dvec3>& positions,
                                   const std::vector<std::array<std::uint32_t, 3>>& triangles, std::size_t r,
                                   std::uint64_t seed) {
    std::vector<double> area(triangles.size());
    double total = 0.0;
    for (std::size_t f = 0; f < triangles.size(); ++f) {
        const auto& t = triangles[f];
        area[f] = 0.5 * glm::length(glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]));
        total += area[f];
    }
    std::vector<MeshSample> out;
    // An infinite total (a surface of coordinates near 1e300) would make every share NaN.
    if (!(total > 0.0) || !std::isfinite(total) || r == 0) return out;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    for (std::size_t f = 0; f < triangles.size(); ++f) {
        const double expected = double(r) * area[f] / total;
        std::size_t n = std::size_t(expected);
        if (U(rng) < expected - double(n)) ++n;  // fractional placement
        const auto& t = triangles[f];
        for (std::size_t q = 0; q < n; ++q) {
            const double a = std::sqrt(U(rng)), b = U(rng);  // uniform in the triangle
            out.push_back({std::uint32_t(f), (1 - a) * positions[t[0]] + a * (1 - b) * positions[t[1]] + a * b * positions[t[2]]});
        }
    }
    return out;
}

Stroke grow_stroke(const Surface& s, std::uint32_t surface_index, glm::dvec2 uv, StrokeField field,
                   const StrokeOptions& o) {
    Stroke st;
    st.surface = surface_index;
    st.seed_uv = uv;
    const SurfacePoint p = s.eval(uv.x, uv.y);
    st.seed = p.p;
    st.normal = unit_normal(p, s.sign);
    glm::dvec2 d;
    glm::dvec3 T;
    double k = 0;
    std::vector<glm::dvec3> fwd, bwd;
    std::vector<glm::dvec2> fuv, buv;
    if (field_direction(s, uv, field, o, glm::dvec3(0.0), d, T, k)) {
        march(s, uv, field, o, T, 0.5 * o.length, fwd, fuv);
        march(s, uv, field, o, -T, 0.5 * o.length, bwd, buv);
    }
    for (std::size_t i = bwd.size(); i-- > 0;) st.points.push_back(bwd[i]), st.uv.push_back(buv[i]);
    st.seed_at = st.points.size();
    st.points.push_back(st.seed);
    st.uv.push_back(uv);
    for (std::size_t i = 0; i < fwd.size(); ++i) st.points.push_back(fwd[i]), st.uv.push_back(fuv[i]);
    st.arc.assign(st.points.size(), 0.0);
    for (std::size_t i = 1; i < st.points.size(); ++i) st.arc[i] = st.arc[i - 1] + glm::length(st.points[i] - st.points[i - 1]);
    return st;
}

std::vector<Stroke> grow_strokes(const SurfaceList& surfaces, const std::vector<SurfaceSample>& samples,
                                 const StrokeOptions& o) {
    std::vector<Stroke> all(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        StrokeField f = o.field;
        if (f == StrokeField::Iso) f = i % 2 ? StrokeField::IsoU : StrokeField::IsoV;
        if (f == StrokeField::Curvature) f = i % 2 ? StrokeField::CurvatureMin : StrokeField::CurvatureMax;
        all[i] = grow_stroke(*surfaces[samples[i].surface], samples[i].surface, samples[i].uv, f, o);
    }
    std::vector<Stroke> out;
    out.reserve(all.size());
    for (auto& s : all)
        if (glm::length(s.normal) > 0.5 && s.points.size() >= 2) out.push_back(std::move(s));
    return out;
}

}  // namespace inkline::freeform
