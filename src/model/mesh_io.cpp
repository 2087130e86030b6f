#include "model/mesh_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <unordered_map>

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/IO/Options.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "core/error.hpp"

namespace inkline {
namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
using SoupMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

// OpenMesh's ImporterT silently splits faces it cannot add (non-manifold edges, inconsistent
// orientation) into separate components by duplicating vertices. We must see such faces to
// refuse the mesh, so this importer keeps OpenMesh's readers but records the raw polygons.
class SoupImporter : public OpenMesh::IO::ImporterT<SoupMesh> {
public:
    explicit SoupImporter(SoupMesh& m) : OpenMesh::IO::ImporterT<SoupMesh>(m) {}
    OpenMesh::FaceHandle add_face(const VHandles& idx) override {
        std::vector<std::int64_t> f;
        f.reserve(idx.size());
        for (auto h : idx) f.push_back(h.idx());
        polygons.push_back(std::move(f));
        return OpenMesh::FaceHandle();  // no face is built in the OpenMesh mesh
    }
    bool is_triangle_mesh() const override { return false; }  // readers must not pre-split
    std::vector<std::vector<std::int64_t>> polygons;
};

// Silences OpenMesh's console messages while reading; we report our own one-line errors.
struct QuietOpenMesh {
    QuietOpenMesh() {
        omerr().disable();
        omlog().disable();
        omout().disable();
    }
    ~QuietOpenMesh() {
        omerr().enable();
        omlog().enable();
        omout().enable();
    }
};

std::string lower_extension(const std::string& path) {
    const auto dot = path.find_last_of('.');
    const auto slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string e = path.substr(dot + 1);
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
    return e;
}

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
    if (a > b) std::swap(a, b);
    return (std::uint64_t(a) << 32) | b;
}

}  // namespace

TriangleMesh load_mesh(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext != "obj" && ext != "off" && ext != "ply" && ext != "stl")
        throw Error(path, "unsupported mesh format '" + ext + "' (expected .obj, .off, .ply or .stl)");
    {
        std::ifstream probe(path, std::ios::binary);
        if (!probe) throw Error(path, std::string("cannot open: ") + std::strerror(errno));
        if (probe.peek() == std::ifstream::traits_type::eof()) throw Error(path, "file is empty");
    }

    SoupMesh om;
    SoupImporter importer(om);
    OpenMesh::IO::Options opt;
    bool ok = false;
    {
        QuietOpenMesh quiet;
        ok = OpenMesh::IO::IOManager().read(path, importer, opt);
    }
    if (!ok) throw Error(path, "cannot parse as " + ext + " (malformed or truncated file)");

    TriangleMesh mesh;
    mesh.positions.reserve(om.n_vertices());
    for (auto v : om.vertices()) {
        const auto& p = om.point(v);
        mesh.positions.emplace_back(p[0], p[1], p[2]);
    }
    const std::int64_t nv = std::int64_t(mesh.positions.size());
    for (std::size_t fi = 0; fi < importer.polygons.size(); ++fi) {
        const auto& poly = importer.polygons[fi];
        if (poly.size() < 3)
            throw Error(path, "face " + std::to_string(fi) + " has fewer than 3 vertices");
        for (auto i : poly)
            if (i < 0 || i >= nv)
                throw Error(path, "face " + std::to_string(fi) + " refers to vertex " +
                                      std::to_string(i) + " of " + std::to_string(nv));
        if (poly.size() > 3) ++mesh.polygons_triangulated;
        // Fan triangulation, as OpenMesh's own triangulate() does for convex polygons.
        for (std::size_t k = 1; k + 1 < poly.size(); ++k)
            mesh.triangles.push_back({std::uint32_t(poly[0]), std::uint32_t(poly[k]),
                                      std::uint32_t(poly[k + 1])});
    }
    validate_mesh(mesh, path);
    return mesh;
}

void validate_mesh(TriangleMesh& mesh, const std::string& where) {
    const std::size_t nv = mesh.positions.size();
    for (std::size_t i = 0; i < nv; ++i) {
        const auto& p = mesh.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw Error(where, "vertex " + std::to_string(i) + " has a NaN or infinite coordinate");
    }
    if (mesh.triangles.empty()) throw Error(where, "mesh has no faces");
    const std::size_t nf = mesh.triangles.size();
    for (std::size_t f = 0; f < nf; ++f) {
        const auto& t = mesh.triangles[f];
        for (auto i : t)
            if (i >= nv)
                throw Error(where, "face " + std::to_string(f) + " refers to vertex " +
                                       std::to_string(i) + " of " + std::to_string(nv));
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
            throw Error(where, "face " + std::to_string(f) + " repeats a vertex index");
    }

    // Undirected edge -> incident faces. More than two is a non-manifold edge.
    std::unordered_map<std::uint64_t, std::array<std::uint32_t, 2>> edge_faces;
    edge_faces.reserve(nf * 2);
    std::size_t nonmanifold = 0;
    std::uint64_t first_bad = 0;
    for (std::uint32_t f = 0; f < nf; ++f) {
        for (int k = 0; k < 3; ++k) {
            const auto key = edge_key(mesh.triangles[f][k], mesh.triangles[f][(k + 1) % 3]);
            auto [it, inserted] = edge_faces.try_emplace(key, std::array<std::uint32_t, 2>{f, UINT32_MAX});
            if (inserted) continue;
            if (it->second[1] == UINT32_MAX) {
                it->second[1] = f;
            } else {
                if (nonmanifold++ == 0) first_bad = key;
                it->second[1] = UINT32_MAX - 1;  // poisoned: counted once more is fine
            }
        }
    }
    if (nonmanifold > 0)
        throw Error(where, "non-manifold: " + std::to_string(nonmanifold) +
                               " extra face(s) on edges shared by more than two faces (first at vertices " +
                               std::to_string(first_bad >> 32) + "-" +
                               std::to_string(first_bad & 0xffffffffu) +
                               "); hidden-line removal by quantitative invisibility needs a 2-manifold mesh");

    // Consistent orientation by breadth-first search over faces: two faces sharing an edge must
    // traverse it in opposite directions. A conflict means the surface is not orientable.
    auto directed = [&](std::uint32_t f, std::uint32_t a, std::uint32_t b) {
        const auto& t = mesh.triangles[f];
        for (int k = 0; k < 3; ++k)
            if (t[k] == a && t[(k + 1) % 3] == b) return true;
        return false;
    };
    std::vector<std::int8_t> state(nf, 0);  // 0 unvisited, 1 keep, -1 flip
    std::vector<std::uint32_t> queue;
    std::vector<std::uint32_t> component(nf, 0);
    std::uint32_t ncomp = 0;
    for (std::uint32_t seed = 0; seed < nf; ++seed) {
        if (state[seed] != 0) continue;
        state[seed] = 1;
        component[seed] = ncomp;
        queue.assign(1, seed);
        for (std::size_t qi = 0; qi < queue.size(); ++qi) {
            const std::uint32_t f = queue[qi];
            const auto& t = mesh.triangles[f];
            for (int k = 0; k < 3; ++k) {
                std::uint32_t a = t[k], b = t[(k + 1) % 3];
                if (state[f] < 0) std::swap(a, b);  // direction after the flip decided for f
                const auto& ef = edge_faces.at(edge_key(a, b));
                if (ef[1] == UINT32_MAX) continue;  // border edge
                const std::uint32_t g = ef[0] == f ? ef[1] : ef[0];
                // g must traverse b->a after its own flip state.
                const bool g_ab = directed(g, a, b);
                const std::int8_t need = g_ab ? -1 : 1;
                if (state[g] == 0) {
                    state[g] = need;
                    component[g] = ncomp;
                    queue.push_back(g);
                } else if (state[g] != need) {
                    throw Error(where, "non-orientable surface (faces " + std::to_string(f) + " and " +
                                           std::to_string(g) +
                                           " cannot be oriented consistently, e.g. a Moebius strip)");
                }
            }
        }
        ++ncomp;
    }
    for (std::uint32_t f = 0; f < nf; ++f)
        if (state[f] < 0) {
            std::swap(mesh.triangles[f][1], mesh.triangles[f][2]);
            ++mesh.faces_reoriented;
        }

    // Closed components are turned outward (positive signed volume), so that front-facing
    // silhouette edges are the convex ones, as the Markosian et al. parity rule assumes.
    std::vector<double> volume(ncomp, 0.0);
    std::vector<char> closed(ncomp, 1);
    for (const auto& [key, ef] : edge_faces)
        if (ef[1] == UINT32_MAX) closed[component[ef[0]]] = 0;
    const glm::dvec3 c = mesh.positions[mesh.triangles[0][0]];
    for (std::uint32_t f = 0; f < nf; ++f) {
        const auto& t = mesh.triangles[f];
        const glm::dvec3 a = mesh.positions[t[0]] - c, b = mesh.positions[t[1]] - c,
                         d = mesh.positions[t[2]] - c;
        volume[component[f]] += a.x * (b.y * d.z - b.z * d.y) - a.y * (b.x * d.z - b.z * d.x) +
                                a.z * (b.x * d.y - b.y * d.x);
    }
    for (std::uint32_t f = 0; f < nf; ++f)
        if (closed[component[f]] && volume[component[f]] < 0.0) {
            std::swap(mesh.triangles[f][1], mesh.triangles[f][2]);
            ++mesh.faces_reoriented;
        }
}

}  // namespace inkline
