#include "style/noise.hpp"

#include <cmath>
#include <numeric>

namespace inkline {

PerlinNoise::PerlinNoise(std::uint32_t seed) {
    std::array<std::uint8_t, 256> p;
    std::iota(p.begin(), p.end(), 0);
    // Fisher-Yates with a fixed 32-bit LCG: the same seed gives the same table on every machine.
    std::uint32_t state = seed * 2654435761u + 12345u;
    for (int i = 255; i > 0; --i) {
        state = state * 1664525u + 1013904223u;
        const int j = int((state >> 8) % std::uint32_t(i + 1));
        std::swap(p[std::size_t(i)], p[std::size_t(j)]);
    }
    for (std::size_t i = 0; i < 512; ++i) perm_[i] = p[i & 255];
}

namespace {
double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
double lerp(double a, double b, double t) { return a + t * (b - a); }
// Dot product of the offset (x, y) with one of 8 gradients (axes and diagonals).
double grad(std::uint8_t h, double x, double y) {
    switch (h & 7) {
        case 0: return x + y;
        case 1: return -x + y;
        case 2: return x - y;
        case 3: return -x - y;
        case 4: return x;
        case 5: return -x;
        case 6: return y;
        default: return -y;
    }
}
}  // namespace

double PerlinNoise::operator()(double x, double y) const {
    const double fx = std::floor(x), fy = std::floor(y);
    const int X = int(static_cast<long long>(fx) & 255), Y = int(static_cast<long long>(fy) & 255);
    x -= fx;
    y -= fy;
    const double u = fade(x), v = fade(y);
    const auto h = [&](int i, int j) { return perm_[std::size_t(perm_[std::size_t(X + i)] + Y + j)]; };
    const double n00 = grad(h(0, 0), x, y), n10 = grad(h(1, 0), x - 1, y);
    const double n01 = grad(h(0, 1), x, y - 1), n11 = grad(h(1, 1), x - 1, y - 1);
    return lerp(lerp(n00, n10, u), lerp(n01, n11, u), v);
}

glm::dvec2 noise_offset(const PerlinNoise& noise, const glm::dvec2& p, const glm::dvec2& T, double normal_amp,
                        double tangent_amp, double wavelength) {
    const glm::dvec2 q = p / wavelength, N(-T.y, T.x);
    const double a = normal_amp != 0.0 ? noise(q) : 0.0;
    const double b = tangent_amp != 0.0 ? noise(q.x + 57.31, q.y + 113.7) : 0.0;
    return normal_amp * a * N + tangent_amp * b * T;
}

}  // namespace inkline
