// Beyond the seed: the accepted pixels traced into polylines, so that stroke styles and SVG
// editing apply to tone lines as to the object-space ones.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/clock.hpp"
#include "tone/tone.hpp"

namespace inkline::tone {

namespace {

constexpr float kMinTurnCos = 0.7071f;  // consecutive points' directions within 45 degrees

struct Tracer {
    const RidgeField& f;
    std::vector<std::uint8_t> thin;  // 1: a line's centre pixel, not yet chained

    std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(f.width) + std::size_t(x); }
    float opacity_at(int x, int y) const {
        return x < 0 || y < 0 || x >= f.width || y >= f.height ? 0.0f : f.opacity[index(x, y)];
    }

    // Non-maximum suppression across the line: a pixel is kept when its opacity is not below its
    // neighbour's on either side (ties go to the one nearer its ridge point), so a line of width w
    // leaves one pixel across.
    void thin_out(float min_opacity) {
        thin.assign(f.opacity.size(), 0);
        for (int y = 0; y < f.height; ++y)
            for (int x = 0; x < f.width; ++x) {
                const std::size_t i = index(x, y);
                const float o = f.opacity[i];
                if (!(o >= min_opacity) || o <= 0.0f) continue;
                const glm::vec2 n(-f.direction[i].y, f.direction[i].x);
                // The 8-neighbour step closest to the normal.
                const int dx = std::abs(n.x) > 0.3827f ? (n.x > 0 ? 1 : -1) : 0;
                const int dy = std::abs(n.y) > 0.3827f ? (n.y > 0 ? 1 : -1) : 0;
                const glm::vec2 centre(x + 0.5f, y + 0.5f);
                const float d_here = glm::length(f.point[i] - centre);
                bool keep = true;
                for (int s : {1, -1}) {
                    const int nx = x + s * dx, ny = y + s * dy;
                    const float on = opacity_at(nx, ny);
                    if (on > o) keep = false;
                    else if (on == o && on > 0.0f &&
                             glm::length(f.point[index(nx, ny)] - glm::vec2(nx + 0.5f, ny + 0.5f)) < d_here)
                        keep = false;
                }
                thin[i] = keep;
            }
    }

    // The next thin pixel from `at` going along `dir` (8-neighbours first, then the 5 x 5 ring to
    // bridge a one-pixel gap); -1 when none.
    long next(std::size_t at, const glm::vec2& dir) const {
        const int x = int(at % std::size_t(f.width)), y = int(at / std::size_t(f.width));
        const glm::vec2 p = f.point[at];
        for (int ring = 1; ring <= 2; ++ring) {
            long best = -1;
            float best_score = 1e30f;
            for (int dy = -ring; dy <= ring; ++dy)
                for (int dx = -ring; dx <= ring; ++dx) {
                    if (std::max(std::abs(dx), std::abs(dy)) != ring) continue;
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= f.width || ny >= f.height) continue;
                    const std::size_t j = index(nx, ny);
                    if (!thin[j]) continue;
                    const glm::vec2 v = f.point[j] - p;
                    const float along = glm::dot(v, dir);
                    if (along <= 0.0f || std::abs(glm::dot(f.direction[j], dir)) < kMinTurnCos) continue;
                    const float across = std::abs(v.x * dir.y - v.y * dir.x);
                    const float score = across * 2.0f + along;
                    if (score < best_score) best_score = score, best = long(j);
                }
            if (best >= 0) return best;
        }
        return -1;
    }

    // Follows the line from `start` along `dir`, consuming thin pixels; appends the pixels.
    void follow(std::size_t start, glm::vec2 dir, std::vector<std::size_t>& out) {
        std::size_t at = start;
        for (long j; (j = next(at, dir)) >= 0;) {
            const glm::vec2 d = f.direction[std::size_t(j)];
            const glm::vec2 step = f.point[std::size_t(j)] - f.point[at];
            dir = glm::dot(d, dir) >= 0 ? d : -d;
            if (glm::dot(step, dir) <= 0) dir = glm::dot(step, step) > 0 ? glm::normalize(step) : dir;
            at = std::size_t(j);
            thin[at] = 0;
            out.push_back(at);
        }
    }
};

}  // namespace

std::vector<Piece> trace_lines(const RidgeField& field, LineKind kind, const ToneOptions& options) {
    Tracer t{field, {}};
    // Hysteresis (as Canny's): a line is followed through pixels down to a quarter of the least
    // opacity, and kept when it reaches that least opacity somewhere, so that counterchange's
    // faint stretches do not cut lines into dashes.
    t.thin_out(float(options.min_opacity) * 0.25f);
    const double min_length = options.min_length >= 0 ? options.min_length : options.width;
    std::vector<Piece> pieces;
    std::vector<std::size_t> forward, backward;
    for (std::size_t i = 0; i < t.thin.size(); ++i) {
        if (!t.thin[i]) continue;
        t.thin[i] = 0;
        forward.clear();
        backward.clear();
        t.follow(i, field.direction[i], forward);
        t.follow(i, -field.direction[i], backward);
        if (forward.size() + backward.size() < 1) continue;
        Piece p;
        p.kind = kind;
        p.curve = std::uint32_t(pieces.size());
        std::reverse(backward.begin(), backward.end());
        backward.push_back(i);
        backward.insert(backward.end(), forward.begin(), forward.end());
        double length = 0.0;
        float strongest = 0.0f;
        for (std::size_t k = 0; k < backward.size(); ++k) {
            const std::size_t j = backward[k];
            p.points.push_back(glm::dvec2(field.point[j]));
            p.opacity.push_back(field.opacity[j]);
            if (!field.width_scale.empty()) p.width.push_back(field.width_scale[j]);
            strongest = std::max(strongest, field.opacity[j]);
            if (k > 0) length += glm::length(p.points[k] - p.points[k - 1]);
        }
        if (length < min_length || strongest < float(options.min_opacity)) continue;
        pieces.push_back(std::move(p));
    }
    return pieces;
}

void render_tone(const MeshTopology& mesh, const ToneMesh& normals, const Camera& camera, const ToneOptions& options,
                 bool dark, bool highlight, ToneResult& out, bool trace) {
    auto t0 = std::chrono::steady_clock::now();
    shade(mesh, normals, camera, options, out.shaded);
    out.seconds.shade = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    gaussian_blur(out.shaded.tone, options.width, out.tone_blurred, options.threads, &out.blur_scratch);
    if (highlight)
        gaussian_blur(out.shaded.specular, options.width, out.specular_blurred, options.threads, &out.blur_scratch);
    out.seconds.blur = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    out.dark = {};
    out.highlight = {};
    if (dark || highlight)
        detect_ridges_both(out.tone_blurred, out.tone_blurred, dark ? &out.dark : nullptr,
                           highlight ? &out.highlight : nullptr, options, &out.shaded.width_scale);
    if (highlight) {
        // The specular channel's own tone is its counterchange: a highlight is as strong as it is bright.
        detect_ridges(out.specular_blurred, out.specular_blurred, Polarity::Light, options.highlight_lower,
                      options.highlight_upper, options, out.specular, &out.shaded.width_scale);
        merge_max(out.highlight, out.specular);
    }
    out.seconds.ridges = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    out.pieces.clear();
    if (!trace) dark = highlight = false;
    if (dark) out.pieces = trace_lines(out.dark, LineKind::ToneDark, options);
    if (highlight)
        for (Piece& p : trace_lines(out.highlight, LineKind::ToneHighlight, options)) out.pieces.push_back(std::move(p));
    out.seconds.trace = seconds_since(t0);
}

}  // namespace inkline::tone
