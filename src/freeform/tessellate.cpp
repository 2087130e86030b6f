#include "freeform/tessellate.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "core/error.hpp"
#include "model/topology.hpp"
#include "visibility/ray_caster.hpp"

namespace inkline::freeform {
namespace {

std::array<int, 2> grid_size(const Surface& s, const TessellationOptions& o) {
    if (dynamic_cast<const BezierPatch*>(&s)) return {o.bezier_segments, o.bezier_segments};
    if (const auto* n = dynamic_cast<const NurbsSurface*>(&s))  // a Bezier patch's worth per knot span
        return {std::min(4096, o.bezier_segments * n->spans_u()), std::min(4096, o.bezier_segments * n->spans_v())};
    const int n = std::max(8, o.primitive_segments);
    if (dynamic_cast<const Sphere*>(&s)) return {n / 2, n};
    return {n, n / 2};  // torus: around the ring, around the tube
}

struct CellKey {
    std::int64_t x, y, z;
    bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
    std::size_t operator()(const CellKey& k) const {
        return std::size_t(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
    }
};

}  // namespace

Tessellation tessellate(SurfaceList& surfaces, const TessellationOptions& options, const std::string& where) {
    if (surfaces.empty()) throw Error(where, "no surfaces");
    if (options.bezier_segments < 1 || options.bezier_segments > 1024 || options.primitive_segments < 8 ||
        options.primitive_segments > 8192)
        throw Error(where, "tessellation segments out of range");
    // The grids' size is known before anything is evaluated: refuse what would take gigabytes
    // (about 200 bytes per grid point by the end: points, welded mesh, topology). The CLI's finest
    // --tessellation (512) on the teapot's 32 patches needs 8.4 M.
    constexpr std::size_t kMaxGridPoints = 9000000;
    std::size_t grid_points = 0;
    for (const auto& sp : surfaces) {
        const auto [nu, nv] = grid_size(*sp, options);
        grid_points += std::size_t(nu + 1) * std::size_t(nv + 1);
        if (grid_points > kMaxGridPoints)
            throw Error(where, "tessellating " + std::to_string(surfaces.size()) + " surfaces needs more than " +
                                   std::to_string(kMaxGridPoints) +
                                   " grid points (fewer or smaller surfaces, or a lower --tessellation)");
    }
    Tessellation t;
    // Grid points.
    Bounds3 box{glm::dvec3(1e300), glm::dvec3(-1e300)};
    for (auto& sp : surfaces) {
        const Surface& s = *sp;
        auto [nu, nv] = grid_size(s, options);
        Tessellation::Grid g{nu, nv, t.points.size(), t.cell_faces.size()};
        for (int i = 0; i <= nu; ++i)
            for (int j = 0; j <= nv; ++j) {
                const double u = s.u_range[0] + (s.u_range[1] - s.u_range[0]) * i / nu;
                const double v = s.v_range[0] + (s.v_range[1] - s.v_range[0]) * j / nv;
                const glm::dvec3 p = s.eval(u, v).p;
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                    throw Error(where, s.name() + " evaluates to a NaN or infinite point");
                t.points.push_back(p);
                box.lo = glm::min(box.lo, p);
                box.hi = glm::max(box.hi, p);
            }
        t.cell_faces.resize(t.cell_faces.size() + std::size_t(nu) * nv, {UINT32_MAX, UINT32_MAX});
        t.grids.push_back(g);
    }
    // Weld: points within tol share a vertex (hash of tol-sized cells, neighbours checked).
    const double diag = std::max(glm::length(box.hi - box.lo), 1e-300);
    if (!std::isfinite(diag)) throw Error(where, "the surfaces' bounding box is too large for a double (coordinates near 1e300)");
    const double tol = 1e-7 * diag;
    std::unordered_map<CellKey, std::vector<std::uint32_t>, CellHash> cells;
    std::vector<std::uint32_t> vertex_of(t.points.size());
    for (std::size_t k = 0; k < t.points.size(); ++k) {
        const glm::dvec3 p = t.points[k];
        // Cells counted from the box's corner: 0 .. 1e7 whatever the offset (from the origin, a
        // surface far away, 1e24 with a diagonal of 3, overflowed the integer: fuzz/run.sh surfaces).
        const glm::dvec3 q = (p - box.lo) / tol;
        const CellKey c{std::int64_t(std::floor(q.x)), std::int64_t(std::floor(q.y)), std::int64_t(std::floor(q.z))};
        std::uint32_t found = UINT32_MAX;
        for (int dx = -1; dx <= 1 && found == UINT32_MAX; ++dx)
            for (int dy = -1; dy <= 1 && found == UINT32_MAX; ++dy)
                for (int dz = -1; dz <= 1 && found == UINT32_MAX; ++dz) {
                    auto it = cells.find({c.x + dx, c.y + dy, c.z + dz});
                    if (it == cells.end()) continue;
                    for (std::uint32_t v : it->second)
                        if (glm::length(t.mesh.positions[v] - p) <= tol) { found = v; break; }
                }
        if (found == UINT32_MAX) {
            found = std::uint32_t(t.mesh.positions.size());
            t.mesh.positions.push_back(p);
            cells[c].push_back(found);
        } else {
            ++t.welded;
        }
        vertex_of[k] = found;
    }
    // Triangles, oriented like S_u x S_v; collapsed ones dropped.
    std::vector<std::uint32_t> tri_surface;
    for (std::size_t s = 0; s < surfaces.size(); ++s) {
        const auto& g = t.grids[s];
        auto id = [&](int i, int j) { return vertex_of[g.first_point + std::size_t(i) * (g.nv + 1) + j]; };
        for (int i = 0; i < g.nu; ++i)
            for (int j = 0; j < g.nv; ++j) {
                const std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
                const std::array<std::array<std::uint32_t, 3>, 2> tris{{{a, b, c}, {a, c, d}}};
                for (int h = 0; h < 2; ++h) {
                    const auto& tr = tris[h];
                    if (tr[0] == tr[1] || tr[1] == tr[2] || tr[0] == tr[2]) {
                        ++t.dropped;
                        continue;
                    }
                    t.cell_faces[g.first_cell + std::size_t(i) * g.nv + j][h] = std::uint32_t(t.mesh.triangles.size());
                    t.mesh.triangles.push_back(tr);
                    tri_surface.push_back(std::uint32_t(s));
                }
            }
    }
    const auto before = t.mesh.triangles;
    validate_mesh(t.mesh, where);
    // Connected parts (union-find over shared vertices) and their outward orientation by ray parity.
    const std::size_t nf = t.mesh.triangles.size();
    std::vector<std::uint32_t> parent(t.mesh.positions.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const auto& tr : t.mesh.triangles) {
        parent[find(tr[1])] = find(tr[0]);
        parent[find(tr[2])] = find(tr[0]);
    }
    MeshTopology topo = build_topology(t.mesh);
    RayCaster rays(topo);
    std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> parts;
    for (std::uint32_t f = 0; f < nf; ++f) parts[find(t.mesh.triangles[f][0])].push_back(f);
    for (auto& [root, faces] : parts) {
        (void)root;
        // Vote with up to 31 of the largest faces.
        std::vector<std::pair<double, std::uint32_t>> by_area;
        for (std::uint32_t f : faces) {
            const auto& tr = t.mesh.triangles[f];
            const glm::dvec3 n = glm::cross(t.mesh.positions[tr[1]] - t.mesh.positions[tr[0]],
                                            t.mesh.positions[tr[2]] - t.mesh.positions[tr[0]]);
            by_area.push_back({glm::length(n), f});
        }
        const std::size_t k = std::min<std::size_t>(31, by_area.size());
        std::partial_sort(by_area.begin(), by_area.begin() + long(k), by_area.end(), std::greater<>());
        int outward = 0, inward = 0;
        for (std::size_t q = 0; q < k; ++q) {
            const auto& tr = t.mesh.triangles[by_area[q].second];
            const glm::dvec3 a = t.mesh.positions[tr[0]], b = t.mesh.positions[tr[1]], c = t.mesh.positions[tr[2]];
            // A face without a usable normal (collinear corners, or a cross product that underflows
            // on tiny coordinates) has no vote: Embree aborts on a NaN ray (fuzz/run.sh bpt).
            const glm::dvec3 cr = glm::cross(b - a, c - a);
            const double len = glm::length(cr);
            if (!(len > 0.0) || !std::isfinite(len)) continue;
            const glm::dvec3 n = cr / len;
            const glm::dvec3 m = (a + b + c) / 3.0;
            const int layers = rays.count_layers(m + 1e-6 * diag * n, m + 4.0 * diag * n, by_area[q].second, UINT32_MAX);
            (layers % 2 == 0 ? outward : inward)++;
        }
        if (inward > outward)
            for (std::uint32_t f : faces) std::swap(t.mesh.triangles[f][1], t.mesh.triangles[f][2]);
    }
    // Each surface's normal sign follows the majority of its triangles.
    std::vector<long> agree(surfaces.size(), 0);
    for (std::size_t f = 0; f < nf; ++f) agree[tri_surface[f]] += t.mesh.triangles[f] == before[f] ? 1 : -1;
    for (std::size_t s = 0; s < surfaces.size(); ++s) {
        surfaces[s]->sign = agree[s] >= 0 ? 1.0 : -1.0;
        if (agree[s] < 0) ++t.flipped_surfaces;
    }
    return t;
}

glm::dvec3 Tessellation::locate(const SurfaceList& surfaces, std::size_t s, glm::dvec2 uv, std::uint32_t& face,
                                std::uint32_t& other) const {
    const Surface& S = *surfaces[s];
    const Grid& g = grids[s];
    const double x = (uv.x - S.u_range[0]) / (S.u_range[1] - S.u_range[0]) * g.nu;
    const double y = (uv.y - S.v_range[0]) / (S.v_range[1] - S.v_range[0]) * g.nv;
    const int i = std::clamp(int(std::floor(x)), 0, g.nu - 1), j = std::clamp(int(std::floor(y)), 0, g.nv - 1);
    const double a = std::clamp(x - i, 0.0, 1.0), b = std::clamp(y - j, 0.0, 1.0);
    auto P = [&](int di, int dj) { return points[g.first_point + std::size_t(i + di) * (g.nv + 1) + (j + dj)]; };
    const auto& cf = cell_faces[g.first_cell + std::size_t(i) * g.nv + j];
    // Triangle (00, 10, 11) where a >= b, else (00, 11, 01).
    if (a >= b) {
        face = cf[0];
        other = cf[1];
        return P(0, 0) + a * (P(1, 0) - P(0, 0)) + b * (P(1, 1) - P(1, 0));
    }
    face = cf[1];
    other = cf[0];
    return P(0, 0) + b * (P(0, 1) - P(0, 0)) + a * (P(1, 1) - P(0, 1));
}

}  // namespace inkline::freeform
