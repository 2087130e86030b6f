// Sections 3.1-3.3 of the seed: the blur, the least-squares quadratic at each pixel, the search
// toward the ridge, and the opacity.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "tone/parallel.hpp"
#include "tone/tone.hpp"

namespace inkline::tone {

std::string tone_options_error(const ToneOptions& o) {
    const auto num = [](double v) {
        char b[32];
        std::snprintf(b, sizeof b, "%g", v);
        return std::string(b);
    };
    if (!(o.width > 0.0 && o.width <= 256.0)) return "--tone-width: expected a line width in (0, 256] px, got " + num(o.width);
    if (!(o.beta >= 0.0 && o.beta <= 1.0)) return "--tone-beta: expected a share in [0, 1], got " + num(o.beta);
    if (o.steps < 0 || o.steps > 100) return "--tone-steps: expected 0 to 100 steps";
    const auto thresholds = [&](const char* flag, double lo, double hi) -> std::string {
        if (!(lo >= 0.0 && hi >= 0.0 && std::isfinite(hi)))
            return std::string(flag) + ": expected thresholds CL,CU >= 0";
        if (lo > hi) return std::string(flag) + ": the lower threshold " + num(lo) + " is above the upper " + num(hi);
        return "";
    };
    if (auto e = thresholds("--tone-dark", o.dark_lower, o.dark_upper); !e.empty()) return e;
    if (auto e = thresholds("--tone-highlight", o.highlight_lower, o.highlight_upper); !e.empty()) return e;
    if (!(o.specular_exponent >= 1.0 && o.specular_exponent <= 10000.0))
        return "--specular: expected a Blinn-Phong exponent in [1, 10000], got " + num(o.specular_exponent);
    for (const glm::dvec3& l : o.lights)
        if (!(glm::length(l) > 0.0) || !std::isfinite(glm::length(l))) return "--light: expected a non-zero direction";
    if (o.toon_bands < 2 || o.toon_bands > 4) return "--toon-bands: expected 2 to 4 bands";
    if (!(o.min_opacity >= 0.0 && o.min_opacity <= 1.0)) return "--tone-min-opacity: expected a share in [0, 1]";
    return "";
}

void gaussian_blur(const Image& in, double width, Image& out, int threads) {
    const double sigma = width / 4.0;
    const int radius = sigma > 0 ? int(std::ceil(3.0 * sigma)) : 0;
    if (radius == 0 || in.pixels.empty()) {
        out = in;
        return;
    }
    std::vector<float> kernel(std::size_t(2 * radius + 1));
    double sum = 0.0;
    for (int k = -radius; k <= radius; ++k) sum += kernel[std::size_t(k + radius)] = float(std::exp(-0.5 * k * k / (sigma * sigma)));
    for (float& k : kernel) k = float(k / sum);
    const int W = in.width, H = in.height;
    Image mid;
    mid.resize(W, H, 0.0f);
    out.resize(W, H, 0.0f);
    for_row_bands(threads, H, [&](int y0, int y1) {  // along rows, border clamped
        for (int y = y0; y < y1; ++y) {
            const float* row = &in.pixels[std::size_t(y) * std::size_t(W)];
            float* to = &mid.pixels[std::size_t(y) * std::size_t(W)];
            for (int x = 0; x < W; ++x) {
                float acc = 0.0f;
                if (x >= radius && x + radius < W) {
                    for (int k = -radius; k <= radius; ++k) acc += kernel[std::size_t(k + radius)] * row[x + k];
                } else {
                    for (int k = -radius; k <= radius; ++k)
                        acc += kernel[std::size_t(k + radius)] * row[std::clamp(x + k, 0, W - 1)];
                }
                to[x] = acc;
            }
        }
    });
    for_row_bands(threads, H, [&](int y0, int y1) {  // along columns, a row of output at a time
        for (int y = y0; y < y1; ++y) {
            float* to = &out.pixels[std::size_t(y) * std::size_t(W)];
            for (int k = -radius; k <= radius; ++k) {
                const float kw = kernel[std::size_t(k + radius)];
                const float* from = &mid.pixels[std::size_t(std::clamp(y + k, 0, H - 1)) * std::size_t(W)];
                for (int x = 0; x < W; ++x) to[x] += kw * from[x];
            }
        }
    });
}

const std::array<std::array<double, 9>, 6>& fit_matrix() {
    static const std::array<std::array<double, 9>, 6> H = [] {
        double X[9][6];
        for (int i = 0; i < 9; ++i) {
            const double x = i % 3 - 1, y = i / 3 - 1;
            const double row[6] = {x * x, 2 * x * y, y * y, x, y, 1};
            std::copy(row, row + 6, X[i]);
        }
        // (X^T X | I) reduced to (I | (X^T X)^-1) by Gauss-Jordan with partial pivoting.
        double A[6][12] = {};
        for (int r = 0; r < 6; ++r) {
            for (int c = 0; c < 6; ++c)
                for (int i = 0; i < 9; ++i) A[r][c] += X[i][r] * X[i][c];
            A[r][6 + r] = 1.0;
        }
        for (int c = 0; c < 6; ++c) {
            int p = c;
            for (int r = c + 1; r < 6; ++r)
                if (std::abs(A[r][c]) > std::abs(A[p][c])) p = r;
            std::swap(A[p], A[c]);
            const double d = A[c][c];
            for (double& v : A[c]) v /= d;
            for (int r = 0; r < 6; ++r)
                if (r != c) {
                    const double m = A[r][c];
                    for (int k = 0; k < 12; ++k) A[r][k] -= m * A[c][k];
                }
        }
        std::array<std::array<double, 9>, 6> out{};
        for (int r = 0; r < 6; ++r)
            for (int i = 0; i < 9; ++i)
                for (int c = 0; c < 6; ++c) out[std::size_t(r)][std::size_t(i)] += A[r][6 + c] * X[i][c];
        return out;
    }();
    return H;
}

std::array<double, 6> fit_quadratic(const std::array<double, 9>& t) {
    const auto& H = fit_matrix();
    std::array<double, 6> a{};
    for (std::size_t r = 0; r < 6; ++r)
        for (std::size_t i = 0; i < 9; ++i) a[r] += H[r][i] * t[i];
    return a;
}

RidgeLine ridge_line(const std::array<double, 6>& a) {
    // Eigenvalues of M = [a0 a1; a1 a2] as mean +- half-difference (no cancellation at umbilics).
    const double mean = 0.5 * (a[0] + a[2]), half = std::hypot(0.5 * (a[0] - a[2]), a[1]);
    RidgeLine l;
    l.curvature = mean >= 0 ? mean + half : mean - half;
    l.other = mean >= 0 ? mean - half : mean + half;
    // Eigenvector of curvature: the longer of M's two null-space candidates.
    const glm::dvec2 e1(a[1], l.curvature - a[0]), e2(l.curvature - a[2], a[1]);
    const glm::dvec2 e = glm::dot(e1, e1) >= glm::dot(e2, e2) ? e1 : e2;
    const double len = glm::length(e);
    l.normal = len > 0 ? e / len : glm::dvec2(1, 0);
    // u.c = -(a3 a4).u / (2 lambda) since u is an eigenvector of M: the same formula holds when
    // the other eigenvalue is 0 and c does not exist (the seed's singular case).
    l.offset = l.curvature != 0.0 ? -(a[3] * l.normal.x + a[4] * l.normal.y) / (2.0 * l.curvature) : 0.0;
    const double det = a[0] * a[2] - a[1] * a[1];
    if (det != 0.0) l.centre = glm::dvec2(a[2] * a[3] - a[1] * a[4], a[0] * a[4] - a[1] * a[3]) / (-2.0 * det);
    return l;
}

namespace {

// The other curvature over the larger one above which a fit is a spot, not a line.
constexpr double kSpotRatio = 0.5;

// The 9 samples of the 3 x 3 stencil at spacing `spacing` around (x, y), bilinear. Interior
// stencils (the common case) skip the border clamps; an integral spacing at a pixel centre reads
// pixels directly.
std::array<double, 9> stencil(const Image& img, double x, double y, double spacing) {
    std::array<double, 9> t;
    const double fx = x - 0.5 - spacing, fy = y - 0.5 - spacing;
    const int W = img.width, H = img.height;
    if (fx >= 0.0 && fy >= 0.0 && fx + 2 * spacing < W - 1 && fy + 2 * spacing < H - 1) {
        const float* p = img.pixels.data();
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                const double sx = fx + i * spacing, sy = fy + j * spacing;
                const int x0 = int(sx), y0 = int(sy);
                const float tx = float(sx - x0), ty = float(sy - y0);
                const float* r0 = p + std::size_t(y0) * std::size_t(W) + std::size_t(x0);
                const float* r1 = r0 + W;
                const float top = r0[0] + tx * (r0[1] - r0[0]), bottom = r1[0] + tx * (r1[1] - r1[0]);
                t[std::size_t(3 * j + i)] = top + ty * (bottom - top);
            }
        return t;
    }
    for (int i = 0; i < 9; ++i) t[std::size_t(i)] = img.sample(x + spacing * (i % 3 - 1), y + spacing * (i / 3 - 1));
    return t;
}

RidgeLine fit_at(const Image& img, double x, double y, double spacing) {
    return ridge_line(fit_quadratic(stencil(img, x, y, spacing)));
}

// One pixel: the search toward the line, then the opacity (0 when rejected).
void ridge_pixel(const Image& img, const Image& tone, int px, int py, bool dark, double lower, double upper,
                 const ToneOptions& o, float& opacity, glm::vec2& point, glm::vec2& direction) {
    const double spacing = 0.5 * o.width, half = 0.5 * o.width;
    const glm::dvec2 centre(px + 0.5, py + 0.5);
    glm::dvec2 pos = centre;
    double travel = 0.0;
    RidgeLine l;
    for (int step = 0;; ++step) {
        l = fit_at(img, pos.x, pos.y, spacing);
        const double c = dark ? l.curvature : -l.curvature;  // > 0 on the wanted kind of line
        if (!(c >= lower) || c <= 0.0) return;
        if (step == o.steps) break;
        const double move = o.beta * l.offset * spacing;
        travel += std::abs(move);
        if (travel > half) return;
        pos += move * l.normal;
    }
    glm::dvec2 on_line = pos + l.offset * spacing * l.normal;
    if (l.other * l.curvature > 0.0 && std::abs(l.other) > kSpotRatio * std::abs(l.curvature)) {
        // A spot (both curvatures alike): every pixel around it sees a line through its centre,
        // each at its own angle (a star once traced). One dash through the centre instead,
        // horizontal: c = -M^-1 (a3 a4) / 2 exists, M being definite.
        on_line = pos + spacing * l.centre;
        l.normal = {0.0, 1.0};
    }
    const double distance = glm::dot(centre - on_line, l.normal);
    double alpha = upper > lower ? std::clamp((std::abs(l.curvature) - lower) / (upper - lower), 0.0, 1.0) : 1.0;
    if (o.distance_falloff) alpha *= std::max(0.0, 1.0 - std::abs(distance) / half);
    if (o.counterchange) {
        const double t = std::clamp(double(tone.at(px, py)), 0.0, 1.0);
        alpha *= dark ? 1.0 - t : t;
    }
    if (!(alpha > 0.0)) return;
    opacity = float(alpha);
    point = glm::vec2(centre - distance * l.normal);
    direction = glm::vec2(-l.normal.y, l.normal.x);
}

}  // namespace

void detect_ridges(const Image& channel, const Image& tone, Polarity polarity, double lower, double upper,
                   const ToneOptions& options, RidgeField& out) {
    const int W = channel.width, H = channel.height;
    const std::size_t n = std::size_t(W) * std::size_t(H);
    out.width = W;
    out.height = H;
    out.opacity.assign(n, 0.0f);
    out.point.assign(n, glm::vec2(0.0f));
    out.direction.assign(n, glm::vec2(0.0f));
    const bool dark = polarity == Polarity::Dark;
    for_row_bands(options.threads, H, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                ridge_pixel(channel, tone, x, y, dark, lower, upper, options, out.opacity[i], out.point[i],
                            out.direction[i]);
            }
    });
}

void merge_max(RidgeField& a, const RidgeField& b) {
    for (std::size_t i = 0; i < a.opacity.size(); ++i)
        if (b.opacity[i] > a.opacity[i]) {
            a.opacity[i] = b.opacity[i];
            a.point[i] = b.point[i];
            a.direction[i] = b.direction[i];
        }
}

}  // namespace inkline::tone
