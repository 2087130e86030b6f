// Compact unit vectors for the stored levels (multiscale.hpp): a unit normal in two floats by the
// octahedral map (Meyer et al. 2010), and a tangent direction as one angle in a frame that the
// normal alone fixes (Duff et al. 2017, "Building an orthonormal basis, revisited").
#pragma once

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace inkline {

inline float sign_not_zero(float x) { return x >= 0.0f ? 1.0f : -1.0f; }

inline glm::vec2 octahedral_encode(const glm::vec3& n) {
    const float l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
    if (!(l1 > 0.0f)) return {0.0f, 0.0f};  // no normal: decodes to +z, and the vertex is invalid
    glm::vec2 p(n.x / l1, n.y / l1);
    if (n.z < 0.0f)
        p = {(1.0f - std::fabs(p.y)) * sign_not_zero(p.x), (1.0f - std::fabs(p.x)) * sign_not_zero(p.y)};
    return p;
}

inline glm::vec3 octahedral_decode(const glm::vec2& e) {
    glm::vec3 n(e.x, e.y, 1.0f - std::fabs(e.x) - std::fabs(e.y));
    if (n.z < 0.0f) {
        const float x = n.x;
        n.x = (1.0f - std::fabs(n.y)) * sign_not_zero(x);
        n.y = (1.0f - std::fabs(x)) * sign_not_zero(n.y);
    }
    return glm::normalize(n);
}

// An orthonormal tangent frame (b1, b2) of unit n, continuous except across n.z = 0's sign flip.
inline void tangent_frame(const glm::vec3& n, glm::vec3& b1, glm::vec3& b2) {
    const float s = n.z >= 0.0f ? 1.0f : -1.0f;
    const float a = -1.0f / (s + n.z), b = n.x * n.y * a;
    b1 = {1.0f + s * n.x * n.x * a, s * b, -s * n.x};
    b2 = {b, s + n.y * n.y * a, -n.y};
}

inline float angle_in_frame(const glm::vec3& n, const glm::vec3& d) {
    glm::vec3 b1, b2;
    tangent_frame(n, b1, b2);
    return std::atan2(glm::dot(d, b2), glm::dot(d, b1));
}

inline glm::vec3 direction_in_frame(const glm::vec3& n, float angle) {
    glm::vec3 b1, b2;
    tangent_frame(n, b1, b2);
    return std::cos(angle) * b1 + std::sin(angle) * b2;
}

}  // namespace inkline
