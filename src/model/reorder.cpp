#include "model/reorder.hpp"

#include <algorithm>
#include <utility>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/hilbert_sort.h>
#include <CGAL/property_map.h>

namespace inkline {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

// The points' order along CGAL's Hilbert curve (median policy). The points are sorted with their
// indices beside them, not through an index map: the same comparisons on the same sequence, so
// the same order, without a cache miss per comparison (the sort was the largest share of loading).
std::vector<std::size_t> hilbert_order(std::vector<std::pair<K::Point_3, std::size_t>>& items) {
    using Traits = CGAL::Spatial_sort_traits_adapter_3<K, CGAL::First_of_pair_property_map<std::pair<K::Point_3, std::size_t>>>;
    CGAL::hilbert_sort(items.begin(), items.end(), Traits(), CGAL::Hilbert_sort_median_policy());
    std::vector<std::size_t> order(items.size());
    for (std::size_t i = 0; i < items.size(); ++i) order[i] = items[i].second;
    return order;
}
}  // namespace

TriangleMesh hilbert_ordered(const TriangleMesh& mesh) {
    const std::size_t nv = mesh.positions.size(), nf = mesh.triangles.size();
    std::vector<std::pair<K::Point_3, std::size_t>> items;
    items.reserve(std::max(nv, nf));
    for (std::size_t i = 0; i < nv; ++i) {
        const glm::dvec3& p = mesh.positions[i];
        items.emplace_back(K::Point_3(p.x, p.y, p.z), i);
    }
    const auto vorder = hilbert_order(items);
    std::vector<std::uint32_t> new_index(nv);
    TriangleMesh out = mesh;
    for (std::uint32_t i = 0; i < nv; ++i) {
        new_index[vorder[i]] = i;
        out.positions[i] = mesh.positions[vorder[i]];
    }
    items.clear();
    for (std::size_t f = 0; f < nf; ++f) {
        const auto& t = mesh.triangles[f];
        const glm::dvec3 c = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
        items.emplace_back(K::Point_3(c.x, c.y, c.z), f);
    }
    const auto forder = hilbert_order(items);
    for (std::size_t i = 0; i < nf; ++i) {
        const auto& t = mesh.triangles[forder[i]];
        out.triangles[i] = {new_index[t[0]], new_index[t[1]], new_index[t[2]]};
        if (!mesh.face_object.empty()) out.face_object[i] = mesh.face_object[forder[i]];
    }
    return out;
}

}  // namespace inkline
