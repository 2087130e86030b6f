#include "model/reorder.hpp"

#include <numeric>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/hilbert_sort.h>
#include <CGAL/property_map.h>

namespace inkline {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

std::vector<std::size_t> hilbert_order(const std::vector<K::Point_3>& points) {
    std::vector<std::size_t> order(points.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    using Traits = CGAL::Spatial_sort_traits_adapter_3<K, CGAL::Pointer_property_map<K::Point_3>::const_type>;
    CGAL::hilbert_sort(order.begin(), order.end(), Traits(CGAL::make_property_map(points)),
                       CGAL::Hilbert_sort_median_policy());
    return order;
}
}  // namespace

TriangleMesh hilbert_ordered(const TriangleMesh& mesh) {
    const std::size_t nv = mesh.positions.size(), nf = mesh.triangles.size();
    std::vector<K::Point_3> pts;
    pts.reserve(nv);
    for (const auto& p : mesh.positions) pts.emplace_back(p.x, p.y, p.z);
    const auto vorder = hilbert_order(pts);
    std::vector<std::uint32_t> new_index(nv);
    TriangleMesh out = mesh;
    for (std::uint32_t i = 0; i < nv; ++i) {
        new_index[vorder[i]] = i;
        out.positions[i] = mesh.positions[vorder[i]];
    }
    pts.clear();
    for (const auto& t : mesh.triangles) {
        const glm::dvec3 c = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
        pts.emplace_back(c.x, c.y, c.z);
    }
    const auto forder = hilbert_order(pts);
    for (std::size_t i = 0; i < nf; ++i) {
        const auto& t = mesh.triangles[forder[i]];
        out.triangles[i] = {new_index[t[0]], new_index[t[1]], new_index[t[2]]};
        if (!mesh.face_object.empty()) out.face_object[i] = mesh.face_object[forder[i]];
    }
    return out;
}

}  // namespace inkline
