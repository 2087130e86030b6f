#include "style/hatching.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace inkline {

namespace {

// A hash of (face, k, seed) to [0, 1): particle positions are fixed on the surface, so they do
// not swim from frame to frame.
double unit_hash(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    std::uint64_t x = (std::uint64_t(a) << 32) ^ (std::uint64_t(b) * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(c) << 7);
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdull;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ull;
    x ^= x >> 33;
    return double(x >> 11) * (1.0 / 9007199254740992.0);
}

}  // namespace

std::vector<HatchStroke> hatch_strokes(const MeshTopology& mesh, const Camera& camera, const RayCaster& rays,
                                       const HatchStyle& style, bool check_visibility, HatchStats* stats) {
    HatchStats st;
    std::vector<HatchStroke> out;
    const std::size_t F = mesh.face_count();
    // Area-weighted vertex normals, blended across each triangle.
    std::vector<glm::dvec3> vn(mesh.vertex_count(), glm::dvec3(0.0));
    for (std::size_t f = 0; f < F; ++f) {
        const auto& t = mesh.faces[f];
        const glm::dvec3 n = glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]);
        for (std::uint32_t v : t) vn[v] += n;
    }
    for (auto& n : vn) n = glm::length(n) > 0 ? glm::normalize(n) : n;
    const double R = mesh.bounds.half_diagonal();
    const double length = style.length * R, spacing = style.spacing * R;
    const int segs = std::max(1, style.segments);
    const double near = camera.near_distance();

    for (std::uint32_t f = 0; f < F; ++f) {
        const auto& t = mesh.faces[f];
        const glm::dvec3 A = mesh.positions[t[0]], B = mesh.positions[t[1]], C = mesh.positions[t[2]];
        const glm::dvec3 nf = mesh.face_normal(f);
        if (glm::length(nf) == 0) continue;
        // Barycentric coordinates of a point in the plane of the triangle (clamped to it).
        const glm::dvec3 e0 = B - A, e1 = C - A;
        const double d00 = glm::dot(e0, e0), d01 = glm::dot(e0, e1), d11 = glm::dot(e1, e1);
        const double den = d00 * d11 - d01 * d01;
        if (!(den > 0)) continue;
        const auto blended_normal = [&](const glm::dvec3& p) {
            const glm::dvec3 e2 = p - A;
            const double d20 = glm::dot(e2, e0), d21 = glm::dot(e2, e1);
            double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
            v = std::clamp(v, 0.0, 1.0);
            w = std::clamp(w, 0.0, 1.0 - v);
            const glm::dvec3 n = (1 - v - w) * vn[t[0]] + v * vn[t[1]] + w * vn[t[2]];
            return glm::length(n) > 0 ? glm::normalize(n) : nf;
        };
        int count = 1;
        if (style.by_area) {
            const double expected = 0.5 * std::sqrt(den) / (spacing * spacing);
            count = int(expected) + (unit_hash(f, 0xffffffffu, style.seed) < expected - std::floor(expected) ? 1 : 0);
        }
        for (int k = 0; k < count; ++k) {
            glm::dvec3 P;
            if (style.by_area) {
                double r1 = unit_hash(f, std::uint32_t(2 * k), style.seed), r2 = unit_hash(f, std::uint32_t(2 * k + 1), style.seed);
                if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
                P = A + r1 * e0 + r2 * e1;
            } else {
                P = (A + B + C) / 3.0;
            }
            ++st.particles;
            if (camera.depth(P) <= near) continue;
            const glm::dvec3 O = camera.ray_origin(P);
            const glm::dvec3 view = P - O;
            if (glm::dot(nf, view) >= 0) continue;  // back-facing
            const glm::dvec3 L = style.light_at_camera ? glm::normalize(-view) : style.light;
            const glm::dvec3 n = blended_normal(P);
            const double tone = std::max(0.0, glm::dot(n, L));
            if (tone >= style.threshold) continue;
            ++st.lit;
            if (check_visibility) {
                ++st.ray_tests;
                if (rays.count_layers(O, P, f, kNoFace) != 0) continue;
            }
            // Walk half the length each way from the particle, direction n x view at each step.
            const double step = length / segs;
            std::vector<glm::dvec3> half[2];
            for (int side = 0; side < 2; ++side) {
                glm::dvec3 q = P;
                glm::dvec3 prev_dir(0.0);
                const int n_side = side == 0 ? (segs + 1) / 2 : segs / 2;
                for (int i = 0; i < n_side; ++i) {
                    glm::dvec3 dir = glm::cross(blended_normal(q), q - camera.ray_origin(q));
                    if (glm::length(dir) == 0) break;
                    dir = glm::normalize(dir) * (side ? -1.0 : 1.0);
                    if (glm::length(prev_dir) > 0 && glm::dot(dir, prev_dir) < 0) dir = -dir;
                    prev_dir = dir;
                    q += step * dir;
                    half[side].push_back(q);
                }
            }
            HatchStroke h;
            h.face = f;
            h.centre = P;
            h.tone = tone;
            for (auto it = half[1].rbegin(); it != half[1].rend(); ++it) h.points.push_back(camera.project(*it));
            h.points.push_back(camera.project(P));
            for (const auto& q : half[0]) h.points.push_back(camera.project(q));
            double pix = 0;
            for (std::size_t i = 1; i < h.points.size(); ++i) pix += glm::distance(h.points[i], h.points[i - 1]);
            if (!(pix >= style.min_pixels) || !std::isfinite(pix)) continue;
            ++st.drawn;
            out.push_back(std::move(h));
        }
    }
    if (stats) *stats = st;
    return out;
}

}  // namespace inkline
