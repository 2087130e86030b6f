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

void gaussian_blur(const Image& in, double width, Image& out, int threads, Image* scratch) {
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
    Image local;
    Image& mid = scratch ? *scratch : local;
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
    // (sqrt rather than hypot: tone values are bounded, and hypot's care costs a third of a fit)
    const double d = 0.5 * (a[0] - a[2]), mean = 0.5 * (a[0] + a[2]), half = std::sqrt(d * d + a[1] * a[1]);
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
        const int step = int(spacing);
        if (double(step) == spacing) {
            // A whole-pixel spacing: the 9 samples share their bilinear weights.
            const int x0 = int(fx), y0 = int(fy);
            const float tx = float(fx - x0), ty = float(fy - y0);
            const float w00 = (1 - tx) * (1 - ty), w10 = tx * (1 - ty), w01 = (1 - tx) * ty, w11 = tx * ty;
            for (int j = 0; j < 3; ++j) {
                const float* r0 = p + std::size_t(y0 + j * step) * std::size_t(W) + std::size_t(x0);
                const float* r1 = r0 + W;
                for (int i = 0; i < 3; ++i) {
                    const int o = i * step;
                    t[std::size_t(3 * j + i)] = w00 * r0[o] + w10 * r0[o + 1] + w01 * r1[o] + w11 * r1[o + 1];
                }
            }
            return t;
        }
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

// An upper bound on |curvature| of a fit per unit of its samples' range: the rows of H for a0,
// a1, a2 sum to zero, so |a_r| <= range/2 * sum|H_r|, and |lambda| <= max(|a0|, |a2|) + |a1|
// (Gershgorin). A stencil whose range times this is below c_l is rejected without a fit: the same
// result, at the cost of the samples only (most of an image is background or flat).
double curvature_bound_per_range() {
    static const double k = [] {
        double sum[3] = {0, 0, 0};
        for (int r = 0; r < 3; ++r)
            for (double h : fit_matrix()[std::size_t(r)]) sum[r] += std::abs(h);
        return 0.5 * (std::max(sum[0], sum[2]) + sum[1]);
    }();
    return k;
}

struct Target {
    RidgeField* field = nullptr;  // null: this polarity is not wanted
    double lower = 0.0, upper = 0.0;
};

// One pixel, from its first fit `l` (at the centre): the search toward the line, then the
// opacity (the field is left at 0 when rejected). `scale`: the line width's (section 3.4); the
// thresholds are per (w/2)^2, so per spacing^2 they scale by its square.
void ridge_pixel(const Image& img, const Image& tone, int px, int py, RidgeLine l, bool dark, const Target& target,
                 const ToneOptions& o, double scale) {
    const double spacing = 0.5 * o.width * scale, half = spacing;
    const double lower = target.lower * scale * scale, upper = target.upper * scale * scale;
    const glm::dvec2 centre(px + 0.5, py + 0.5);
    glm::dvec2 pos = centre;
    double travel = 0.0;
    for (int step = 0;; ++step) {
        if (step > 0) l = fit_at(img, pos.x, pos.y, spacing);
        const double c = dark ? l.curvature : -l.curvature;  // > 0 on the wanted kind of line
        if (!(c >= lower) || c <= 0.0) return;
        if (step == o.steps) break;
        const double move = o.beta * l.offset * spacing;
        travel += std::abs(move);
        if (travel > half) return;
        pos += move * l.normal;
    }
    glm::dvec2 on_line = pos + l.offset * spacing * l.normal;
    if (l.other * l.curvature > 0.0) {
        // M definite: c = -M^-1 (a3 a4) / 2 exists. Where the fit at c has both curvatures alike,
        // c is a spot's centre (a round highlight): every pixel around it sees a line through it,
        // each at its own angle (a star once traced). One dash through the centre instead,
        // horizontal. (Decided at c, not at the pixel: on a spot's flank the two differ.)
        const glm::dvec2 c = pos + spacing * l.centre;
        if (glm::length(c - centre) <= half) {
            const RidgeLine at_c = fit_at(img, c.x, c.y, spacing);
            if (at_c.other * at_c.curvature > 0.0 && std::abs(at_c.other) > kSpotRatio * std::abs(at_c.curvature)) {
                on_line = c + spacing * at_c.centre;
                l.normal = {0.0, 1.0};
            }
        }
    }
    const double distance = glm::dot(centre - on_line, l.normal);
    double alpha = upper > lower ? std::clamp((std::abs(l.curvature) - lower) / (upper - lower), 0.0, 1.0) : 1.0;
    if (o.distance_falloff) alpha *= std::max(0.0, 1.0 - std::abs(distance) / half);
    if (o.counterchange) {
        const double t = std::clamp(double(tone.at(px, py)), 0.0, 1.0);
        alpha *= dark ? 1.0 - t : t;
    }
    if (!(alpha > 0.0)) return;
    RidgeField& f = *target.field;
    const std::size_t i = std::size_t(py) * std::size_t(f.width) + std::size_t(px);
    f.opacity[i] = float(alpha);
    f.point[i] = glm::vec2(centre - distance * l.normal);
    f.direction[i] = glm::vec2(-l.normal.y, l.normal.x);
    if (!f.width_scale.empty()) f.width_scale[i] = float(scale);
}

void clear_field(RidgeField* f, int W, int H, bool scaled) {
    if (!f) return;
    const std::size_t n = std::size_t(W) * std::size_t(H);
    f->width = W;
    f->height = H;
    f->opacity.assign(n, 0.0f);
    if (scaled) f->width_scale.assign(n, 1.0f);
    else f->width_scale.clear();
    f->point.assign(n, glm::vec2(0.0f));
    f->direction.assign(n, glm::vec2(0.0f));
}

// The first fit's larger curvature at every pixel of row y in [x0, x1), where the stencil at
// integral spacing `step` lies inside the image: rows 0-2 of H applied to the pixels directly, a
// loop the compiler vectorizes. (The same values as fit_quadratic, up to float rounding.)
void row_curvature(const Image& img, int y, int step, int x0, int x1, float* out) {
    const auto& H = fit_matrix();
    float h[3][9];
    for (int r = 0; r < 3; ++r)
        for (int i = 0; i < 9; ++i) h[r][i] = float(H[std::size_t(r)][std::size_t(i)]);
    const std::size_t W = std::size_t(img.width);
    const float* rows[3] = {&img.pixels[std::size_t(y - step) * W], &img.pixels[std::size_t(y) * W],
                            &img.pixels[std::size_t(y + step) * W]};
    for (int x = x0; x < x1; ++x) {
        float a[3] = {0.0f, 0.0f, 0.0f};
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                const float t = rows[j][x + (i - 1) * step];
                for (int r = 0; r < 3; ++r) a[r] += h[r][3 * j + i] * t;
            }
        const float mean = 0.5f * (a[0] + a[2]), d = 0.5f * (a[0] - a[2]);
        const float half = std::sqrt(d * d + a[1] * a[1]);
        out[x] = mean >= 0.0f ? mean + half : mean - half;
    }
}

// Dark and light lines of one channel in one pass: a pixel's first fit has one sign of
// curvature, so it starts at most one of the two searches. Pixels whose first curvature is
// clearly below the thresholds are skipped without the full fit (a cheap pass over the image
// where the spacing is a whole number of pixels, a bound from the samples' range elsewhere).
void detect(const Image& channel, const Image& tone, const Target& dark, const Target& light, const ToneOptions& o,
            const Image* scale) {
    const int W = channel.width, H = channel.height;
    if (scale && scale->pixels.size() != channel.pixels.size()) scale = nullptr;
    clear_field(dark.field, W, H, scale);
    clear_field(light.field, W, H, scale);
    const double spacing = 0.5 * o.width, bound = curvature_bound_per_range();
    const double dark_lower = dark.field ? dark.lower : 1e300, light_lower = light.field ? light.lower : 1e300;
    const double least = std::min(dark_lower, light_lower);
    const int step = int(spacing);
    const bool integral = double(step) == spacing && step >= 1 && 2 * step < W && 2 * step < H;
    // Float rounding of the quick pass: a pixel within this of a threshold takes the exact path.
    constexpr double kSlack = 1e-4;
    for_row_bands(o.threads, H, [&](int y0, int y1) {
        std::vector<float> quick(std::size_t(W), 0.0f);
        for (int y = y0; y < y1; ++y) {
            const bool inner_row = integral && y >= step && y + step < H;
            if (inner_row) row_curvature(channel, y, step, step, W - step, quick.data());
            for (int x = 0; x < W; ++x) {
                const double s = scale ? double(scale->at(x, y)) : 1.0;
                if (inner_row && x >= step && x + step < W && s == 1.0) {
                    const double c = quick[std::size_t(x)];
                    if (c + kSlack < dark_lower && -c + kSlack < light_lower) continue;
                }
                const std::array<double, 9> t = stencil(channel, x + 0.5, y + 0.5, spacing * s);
                const auto [lo, hi] = std::minmax_element(t.begin(), t.end());
                if ((*hi - *lo) * bound < least * s * s || *hi == *lo) continue;
                const RidgeLine l = ridge_line(fit_quadratic(t));
                const Target& target = l.curvature > 0 ? dark : light;
                if (target.field) ridge_pixel(channel, tone, x, y, l, l.curvature > 0, target, o, s);
            }
        }
    });
}

}  // namespace

void detect_ridges(const Image& channel, const Image& tone, Polarity polarity, double lower, double upper,
                   const ToneOptions& options, RidgeField& out, const Image* scale) {
    const Target wanted{&out, lower, upper};
    if (polarity == Polarity::Dark) detect(channel, tone, wanted, {}, options, scale);
    else detect(channel, tone, {}, wanted, options, scale);
}

void detect_ridges_both(const Image& channel, const Image& tone, RidgeField* dark, RidgeField* light,
                        const ToneOptions& o, const Image* scale) {
    detect(channel, tone, {dark, o.dark_lower, o.dark_upper}, {light, o.highlight_lower, o.highlight_upper}, o, scale);
}

void merge_max(RidgeField& a, const RidgeField& b) {
    for (std::size_t i = 0; i < a.opacity.size(); ++i)
        if (b.opacity[i] > a.opacity[i]) {
            a.opacity[i] = b.opacity[i];
            a.point[i] = b.point[i];
            a.direction[i] = b.direction[i];
            if (!a.width_scale.empty() && !b.width_scale.empty()) a.width_scale[i] = b.width_scale[i];
        }
}

}  // namespace inkline::tone
