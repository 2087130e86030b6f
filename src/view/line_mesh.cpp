#include "view/line_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/common.hpp>

namespace inkline {

namespace {
constexpr std::array<LineStyleGl, 4> kStyles{{
    {0.0f, 1.0f, 0.0f, 0.0f},   // visible
    {0.5f, 0.6f, 6.0f, 4.0f},   // QI 1
    {0.66f, 0.5f, 2.0f, 3.0f},  // QI 2
    {0.8f, 0.4f, 1.0f, 4.0f},   // QI >= 3
}};

// Distance from q to the segment ab.
double distance(const glm::dvec2& q, const glm::dvec2& a, const glm::dvec2& b) {
    const glm::dvec2 ab = b - a, aq = q - a;
    const double l2 = ab.x * ab.x + ab.y * ab.y;
    const double t = l2 > 0.0 ? std::clamp((aq.x * ab.x + aq.y * ab.y) / l2, 0.0, 1.0) : 0.0;
    const glm::dvec2 d = aq - t * ab;
    return std::sqrt(d.x * d.x + d.y * d.y);
}

// Greedy simplification: a point is dropped while the segment from the last kept point to the
// next one passes within `tol` pixels of every dropped point (at most 64 in a row). Dense meshes
// give pieces of many sub-pixel segments; software OpenGL pays per triangle.
void simplify(const std::vector<glm::dvec2>& p, double tol, std::vector<glm::dvec2>& out) {
    out.clear();
    out.push_back(p[0]);
    std::size_t anchor = 0;
    for (std::size_t j = 2; j < p.size(); ++j) {
        bool ok = j - anchor <= 64;
        for (std::size_t k = anchor + 1; k < j && ok; ++k) ok = distance(p[k], p[anchor], p[j]) <= tol;
        if (!ok) {
            out.push_back(p[j - 1]);
            anchor = j - 1;
        }
    }
    out.push_back(p.back());
}

bool finite(const Piece& p) {
    return std::all_of(p.points.begin(), p.points.end(),
                       [](const glm::dvec2& q) { return std::isfinite(q.x) && std::isfinite(q.y); });
}
}  // namespace

const LineStyleGl& line_style(int style) { return kStyles[std::size_t(std::clamp(style, 0, 3))]; }

void build_line_mesh(const Drawing& d, const LineMeshOptions& o, std::vector<LineVertex>& out) {
    out.clear();
    const double width = o.width > 0.0 ? o.width : std::max(1.0, 1.5 * d.camera.height() / 1024.0);
    // Far outside the image nothing is seen; clamping keeps float precision for what is.
    const double lim = 4.0 * std::max(d.camera.width(), d.camera.height());
    std::vector<glm::dvec2> points;
    for (int style = 3; style >= 0; --style) {
        if (style > 0 && !o.hidden) continue;  // (hidden pieces are not drawn: no pass over them)
        const double style_width = width * kStyles[std::size_t(style)].width_scale;
        for (const Piece& p : d.pieces) {
            if (p.points.size() < 2 || !o.kinds[std::size_t(p.kind)]) continue;
            const float half = float(0.5 * style_width * kind_width(p.kind));
            const float reach = half + 1.0f;  // one pixel of antialiasing fringe
            if (std::min(p.qi, 3) != style) continue;
            if (!finite(p)) continue;
            if (o.simplify_px > 0.0) simplify(p.points, o.simplify_px, points);
            const std::vector<glm::dvec2>& pts = o.simplify_px > 0.0 ? points : p.points;
            double along = 0.0;
            for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
                const glm::dvec2 a = glm::clamp(pts[i], -lim, lim), b = glm::clamp(pts[i + 1], -lim, lim);
                const glm::dvec2 ab = b - a;
                const double len = std::sqrt(ab.x * ab.x + ab.y * ab.y);
                if (len <= 0.0) continue;
                const glm::dvec2 t = ab / len, n(-t.y, t.x);
                // Extended by the reach at both ends: round-ish caps and joins without gaps.
                const glm::dvec2 a0 = a - double(reach) * t, b0 = b + double(reach) * t;
                const float s0 = float(along) - reach, s1 = float(along + len) + reach;
                const auto v = [&](const glm::dvec2& c, float side, float s, float u) {
                    const glm::dvec2 q = c + double(side * reach) * n;
                    return LineVertex{float(q.x), float(q.y), side * reach, s, half, float(style), u, float(len)};
                };
                const float u1 = float(len) + reach;
                const LineVertex v0 = v(a0, -1.0f, s0, -reach), v1 = v(a0, 1.0f, s0, -reach),
                                 v2 = v(b0, -1.0f, s1, u1), v3 = v(b0, 1.0f, s1, u1);
                out.insert(out.end(), {v0, v1, v2, v2, v1, v3});
                along += len;
            }
        }
    }
}

}  // namespace inkline
