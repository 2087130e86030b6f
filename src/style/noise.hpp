// Spatially coherent noise for stroke displacement (Markosian et al. 97, section 5: "a
// spatially-coherent noise function indexed by screen-space location"). Classic Perlin gradient
// noise in 2D, implemented by hand (Debian packages no C++ noise library): a fixed permutation of
// 0..255 picks one of 8 unit gradients per lattice point, blended with the quintic fade curve.
#pragma once

#include <array>
#include <cstdint>

#include <glm/vec2.hpp>

namespace inkline {

class PerlinNoise {
public:
    explicit PerlinNoise(std::uint32_t seed = 0);
    // In about [-1, 1]; 0 at every integer lattice point; continuous with continuous gradient.
    double operator()(double x, double y) const;
    double operator()(const glm::dvec2& p) const { return (*this)(p.x, p.y); }

private:
    std::array<std::uint8_t, 512> perm_{};
};

// Displacement of a stroke point at screen position p (px) with unit tangent T and normal N:
// normal_amp * noise(p / wavelength) * N + tangent_amp * noise(p / wavelength + shift) * T.
// Depends on the screen position only (and the local frame): the same point on screen gets the
// same offsets in every stroke and every frame.
glm::dvec2 noise_offset(const PerlinNoise& noise, const glm::dvec2& p, const glm::dvec2& T, double normal_amp,
                        double tangent_amp, double wavelength);

}  // namespace inkline
