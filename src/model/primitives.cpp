#include "model/primitives.hpp"

#include <cmath>

#include <glm/geometric.hpp>

namespace inkline {
namespace {
void quad(TriangleMesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
}
}  // namespace

TriangleMesh make_sphere(glm::dvec3 center, double radius, int slices, int stacks) {
    TriangleMesh m;
    m.positions.push_back(center + glm::dvec3(0, radius, 0));
    for (int i = 1; i < stacks; ++i) {
        const double phi = M_PI * i / stacks;
        for (int j = 0; j < slices; ++j) {
            const double th = 2.0 * M_PI * j / slices;
            m.positions.push_back(center + radius * glm::dvec3(std::sin(phi) * std::cos(th), std::cos(phi),
                                                               std::sin(phi) * std::sin(th)));
        }
    }
    m.positions.push_back(center - glm::dvec3(0, radius, 0));
    const std::uint32_t south = std::uint32_t(m.positions.size() - 1);
    auto ring = [&](int i, int j) { return std::uint32_t(1 + (i - 1) * slices + (j % slices)); };
    for (int j = 0; j < slices; ++j) m.triangles.push_back({0, ring(1, j + 1), ring(1, j)});
    for (int i = 1; i + 1 < stacks; ++i)
        for (int j = 0; j < slices; ++j) quad(m, ring(i, j), ring(i, j + 1), ring(i + 1, j + 1), ring(i + 1, j));
    for (int j = 0; j < slices; ++j) m.triangles.push_back({south, ring(stacks - 1, j), ring(stacks - 1, j + 1)});
    validate_mesh(m, "sphere");
    return m;
}

TriangleMesh make_torus(glm::dvec3 center, glm::dvec3 axis, double R, double r, int nu, int nv) {
    TriangleMesh m;
    const glm::dvec3 w = glm::normalize(axis);
    const glm::dvec3 a = glm::normalize(glm::cross(w, std::abs(w.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 b = glm::cross(w, a);
    for (int i = 0; i < nu; ++i) {
        const double u = 2.0 * M_PI * i / nu;
        const glm::dvec3 radial = std::cos(u) * a + std::sin(u) * b;
        for (int j = 0; j < nv; ++j) {
            const double v = 2.0 * M_PI * j / nv;
            m.positions.push_back(center + (R + r * std::cos(v)) * radial + r * std::sin(v) * w);
        }
    }
    auto id = [&](int i, int j) { return std::uint32_t((i % nu) * nv + (j % nv)); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) quad(m, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
    validate_mesh(m, "torus");
    return m;
}

TriangleMesh make_box(glm::dvec3 lo, glm::dvec3 hi) {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.emplace_back(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    quad(m, 0, 2, 3, 1);  // z = lo
    quad(m, 4, 5, 7, 6);  // z = hi
    quad(m, 0, 1, 5, 4);  // y = lo
    quad(m, 2, 6, 7, 3);  // y = hi
    quad(m, 0, 4, 6, 2);  // x = lo
    quad(m, 1, 3, 7, 5);  // x = hi
    validate_mesh(m, "box");
    return m;
}

TriangleMesh make_sheet(double half_size, double height, int n) {
    TriangleMesh m;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            m.positions.emplace_back(-half_size + 2.0 * half_size * j / n, height, -half_size + 2.0 * half_size * i / n);
    auto id = [&](int i, int j) { return std::uint32_t(i * (n + 1) + j); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) quad(m, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
    validate_mesh(m, "sheet");
    return m;
}

TriangleMesh merge_meshes(const TriangleMesh& a, const TriangleMesh& b) {
    TriangleMesh m = a;
    const auto off = std::uint32_t(a.positions.size());
    m.positions.insert(m.positions.end(), b.positions.begin(), b.positions.end());
    for (auto t : b.triangles) m.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
    validate_mesh(m, "merged mesh");
    return m;
}

}  // namespace inkline
