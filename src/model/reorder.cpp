#include "model/reorder.hpp"

#include <algorithm>
#include <exception>
#include <numeric>
#include <random>
#include <system_error>
#include <thread>
#include <utility>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/hilbert_sort.h>
#include <CGAL/property_map.h>

namespace inkline {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Item = std::pair<K::Point_3, std::uint32_t>;

// The points' order along CGAL's Hilbert curve (median policy). The points are sorted with their
// indices beside them, not through an index map: the same comparisons on the same sequence, so
// the same order, without a cache miss per comparison.
void hilbert_sort_items(std::vector<Item>& items) {
    using Traits = CGAL::Spatial_sort_traits_adapter_3<K, CGAL::First_of_pair_property_map<Item>>;
    CGAL::hilbert_sort(items.begin(), items.end(), Traits(), CGAL::Hilbert_sort_median_policy());
}

std::vector<Item> vertex_items(const TriangleMesh& mesh) {
    std::vector<Item> items;
    items.reserve(mesh.positions.size());
    for (std::uint32_t i = 0; i < mesh.positions.size(); ++i) {
        const glm::dvec3& p = mesh.positions[i];
        items.emplace_back(K::Point_3(p.x, p.y, p.z), i);
    }
    return items;
}

std::vector<Item> face_items(const TriangleMesh& mesh) {
    std::vector<Item> items;
    items.reserve(mesh.triangles.size());
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        const auto& t = mesh.triangles[f];
        const glm::dvec3 c = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
        items.emplace_back(K::Point_3(c.x, c.y, c.z), f);
    }
    return items;
}
}  // namespace

TriangleMesh hilbert_ordered(TriangleMesh mesh, int threads) {
    // The vertices' and the faces' sorts are independent (a face's key is its centroid in the
    // input's positions): with a second thread they run side by side, the same orders either way.
    // Below this many faces a thread's start costs about what it saves.
    constexpr std::size_t kFacesForThread = 4096;
    std::vector<Item> vitems, fitems;
    std::exception_ptr vertex_failure;
    std::thread vertex_thread;
    const auto sort_vertices = [&] {
        try {
            vitems = vertex_items(mesh);
            hilbert_sort_items(vitems);
        } catch (...) {
            vertex_failure = std::current_exception();
        }
    };
    if (threads > 1 && mesh.triangles.size() >= kFacesForThread) {
        try {
            vertex_thread = std::thread(sort_vertices);
        } catch (const std::system_error&) {
            // No thread to be had: this one sorts both.
        }
    }
    fitems = face_items(mesh);
    hilbert_sort_items(fitems);
    if (vertex_thread.joinable()) vertex_thread.join();
    else sort_vertices();
    if (vertex_failure) std::rethrow_exception(vertex_failure);

    const std::size_t nv = mesh.positions.size(), nf = mesh.triangles.size();
    std::vector<std::uint32_t> new_index(nv);
    std::vector<glm::dvec3> positions(nv);
    for (std::uint32_t i = 0; i < nv; ++i) {
        new_index[vitems[i].second] = i;
        positions[i] = mesh.positions[vitems[i].second];
    }
    std::vector<std::array<std::uint32_t, 3>> triangles(nf);
    std::vector<std::uint32_t> face_object(mesh.face_object.empty() ? 0 : nf);
    for (std::size_t i = 0; i < nf; ++i) {
        const auto& t = mesh.triangles[fitems[i].second];
        triangles[i] = {new_index[t[0]], new_index[t[1]], new_index[t[2]]};
        if (!face_object.empty()) face_object[i] = mesh.face_object[fitems[i].second];
    }
    // The corners' pairing, renumbered with the faces (corner k of a face stays corner k).
    if (mesh.corner_mates.size() == 3 * nf && mesh.corner_mates_of == triangles_key(mesh.triangles)) {
        std::vector<std::uint32_t> new_face(nf);
        for (std::uint32_t i = 0; i < nf; ++i) new_face[fitems[i].second] = i;
        std::vector<std::uint32_t> mates(3 * nf);
        for (std::uint32_t i = 0; i < nf; ++i)
            for (std::uint32_t k = 0; k < 3; ++k) {
                const std::uint32_t m = mesh.corner_mates[3 * fitems[i].second + k];
                mates[3 * i + k] = m == kNoCorner ? m : 3 * new_face[m / 3] + m % 3;
            }
        mesh.corner_mates = std::move(mates);
        mesh.corner_mates_of = triangles_key(triangles);
    } else {
        mesh.corner_mates.clear();
    }
    mesh.positions = std::move(positions);
    mesh.triangles = std::move(triangles);
    mesh.face_object = std::move(face_object);
    return mesh;
}

TriangleMesh shuffled_numbering(TriangleMesh mesh, std::uint32_t seed) {
    std::mt19937 rng(seed);
    const std::size_t nv = mesh.positions.size(), nf = mesh.triangles.size();
    std::vector<std::uint32_t> vertex_at(nv), face_at(nf), new_index(nv);
    std::iota(vertex_at.begin(), vertex_at.end(), 0u);
    std::iota(face_at.begin(), face_at.end(), 0u);
    std::shuffle(vertex_at.begin(), vertex_at.end(), rng);
    std::shuffle(face_at.begin(), face_at.end(), rng);
    std::vector<glm::dvec3> positions(nv);
    for (std::uint32_t i = 0; i < nv; ++i) new_index[vertex_at[i]] = i, positions[i] = mesh.positions[vertex_at[i]];
    std::vector<std::array<std::uint32_t, 3>> triangles(nf);
    std::vector<std::uint32_t> face_object(mesh.face_object.empty() ? 0 : nf);
    for (std::size_t i = 0; i < nf; ++i) {
        const auto& t = mesh.triangles[face_at[i]];
        const unsigned r = rng() % 3;
        triangles[i] = {new_index[t[r]], new_index[t[(r + 1) % 3]], new_index[t[(r + 2) % 3]]};
        if (!face_object.empty()) face_object[i] = mesh.face_object[face_at[i]];
    }
    mesh.positions = std::move(positions);
    mesh.triangles = std::move(triangles);
    mesh.face_object = std::move(face_object);
    mesh.corner_mates.clear();
    return mesh;
}

}  // namespace inkline
