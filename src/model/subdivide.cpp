#include "model/subdivide.hpp"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>

#include <vector>

#include "core/error.hpp"

namespace inkline {

TriangleMesh subdivide_loop(TriangleMesh mesh, int levels, const SubdivideProgress& progress) {
    if (levels <= 0) return mesh;
    // (OpenMesh's half-edges hold only orientable surfaces.)
    if (mesh.repairs.orientation_seam_edges > 0)
        throw Error("subdivide", "a non-orientable surface (a Moebius strip, a Klein bottle) cannot be subdivided");
    struct Traits : OpenMesh::DefaultTraits {
        using Point = OpenMesh::Vec3d;
        using Normal = OpenMesh::Vec3d;
    };
    using Mesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;
    TriangleMesh out;
    {
        Mesh m;
        std::vector<Mesh::VertexHandle> vh;
        vh.reserve(mesh.positions.size());
        for (const auto& p : mesh.positions) vh.push_back(m.add_vertex({p.x, p.y, p.z}));
        for (const auto& t : mesh.triangles)
            if (!m.add_face(vh[t[0]], vh[t[1]], vh[t[2]]).is_valid())
                throw Error("subdivide", "OpenMesh refused a face of a validated mesh");
        mesh = TriangleMesh{};  // the input is in m now
        vh = {};
        OpenMesh::Subdivider::Uniform::LoopT<Mesh, double> loop;
        loop.attach(m);
        // Room for the final level at once (with the subdivider's own properties, attached above):
        // the arrays would otherwise grow by doubling, and a doubling holds the old and the new
        // array together (the load's peak; docs/memory.md). Loop: V' = V + E, E' = 2E + 3F, F' = 4F.
        std::size_t nv = m.n_vertices(), ne = m.n_edges(), nf = m.n_faces(), made = 0;
        std::vector<std::size_t> made_by_level;
        for (int l = 0; l < levels; ++l) {
            nv += ne;
            ne = 2 * ne + 3 * nf;
            nf *= 4;
            made += nf;
            made_by_level.push_back(made);
        }
        m.reserve(nv, ne, nf);
        if (progress) progress(0, made);
        for (int l = 0; l < levels; ++l) {  // one level a call: the same mesh as loop(levels)
            loop(1);
            if (progress) progress(made_by_level[std::size_t(l)], made);
        }
        loop.detach();
        out.positions.reserve(m.n_vertices());
        for (const auto v : m.vertices()) {
            const auto& p = m.point(v);
            out.positions.emplace_back(p[0], p[1], p[2]);
        }
        out.triangles.reserve(m.n_faces());
        for (const auto f : m.faces()) {
            std::array<std::uint32_t, 3> tri{};
            int k = 0;
            for (const auto v : m.fv_range(f)) tri[k++] = std::uint32_t(v.idx());
            out.triangles.push_back(tri);
        }
    }  // the OpenMesh copy is freed before the check below
    validate_mesh(out, "subdivide");
    return out;
}

}  // namespace inkline
