#include "model/self_intersections.hpp"

#include <iterator>
#include <utility>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

namespace inkline {

std::vector<std::uint8_t> self_intersecting_faces(const MeshTopology& mesh) {
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    using SM = CGAL::Surface_mesh<K::Point_3>;
    SM sm;
    std::vector<SM::Vertex_index> vs;
    vs.reserve(mesh.vertex_count());
    for (const auto& p : mesh.positions) vs.push_back(sm.add_vertex({p.x, p.y, p.z}));
    std::vector<std::uint32_t> face_of;  // Surface_mesh face -> our face
    face_of.reserve(mesh.face_count());
    std::vector<std::uint8_t> out(mesh.face_count(), 0);
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        const auto& t = mesh.faces[f];
        const SM::Face_index fi = sm.add_face(vs[t[0]], vs[t[1]], vs[t[2]]);
        if (fi == SM::null_face()) {  // cannot happen on a validated 2-manifold; be safe
            out[f] = 1;
            continue;
        }
        face_of.push_back(f);
    }
    std::vector<std::pair<SM::Face_index, SM::Face_index>> pairs;
    CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(pairs));
    for (const auto& [a, b] : pairs) out[face_of[std::size_t(a)]] = out[face_of[std::size_t(b)]] = 1;
    return out;
}

}  // namespace inkline
