// Memory order of a mesh: vertices and faces along a Hilbert curve, so that neighbours on the
// surface are neighbours in memory. Per-view passes that follow the surface (silhouette tracing,
// chaining, walks) then touch a few cache lines instead of the whole mesh.
// Takes a TriangleMesh; gives the same mesh (same orientation, same corners order per face)
// with renumbered vertices and faces. With threads > 1 the vertices' and faces' sorts run on two
// threads, and the corners' pairing is renumbered beside the rest (the same orders and arrays).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "model/mesh_io.hpp"

namespace inkline {

// The order of each point's Hilbert key (hilbert_key of its coordinates quantized to 21 bits an
// axis in the box of the mesh's positions; a face's point is its centroid), ties kept in the input
// order, sorted by radix: linear time. Deterministic: the same mesh gives the same numbering.
TriangleMesh hilbert_ordered(TriangleMesh mesh, int threads = 1);

// The two orders hilbert_ordered renumbers by: vertex i of the result is vertex_at[i], face i
// face_at[i].
struct HilbertOrders {
    std::vector<std::uint32_t> vertex_at, face_at;
};
// hilbert_ordered with the orders known (HilbertOrderAhead: those of this very mesh).
TriangleMesh hilbert_ordered(TriangleMesh mesh, const HilbertOrders& known, int threads = 1);

// hilbert_ordered's orders of a mesh made on a thread of its own while the mesh's owner goes on
// reading it (Model::load: beside the repairs, which leave most files as they are). The thread
// reads the positions and triangles given to start() until it has their keys; the owner must not
// change or free them before calling before_change(), which waits for that and drops the orders
// (the mesh then is no longer the one they are of). take() gives the orders if no change was
// announced, else nothing (hilbert_ordered makes them again).
class HilbertOrderAhead {
public:
    HilbertOrderAhead();
    ~HilbertOrderAhead();  // waits for the thread
    HilbertOrderAhead(const HilbertOrderAhead&) = delete;
    HilbertOrderAhead& operator=(const HilbertOrderAhead&) = delete;
    // Starts the thread (once; nothing if no thread can be had).
    void start(const TriangleMesh& mesh);
    void before_change();
    std::optional<HilbertOrders> take();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// The order before the keys (CGAL's hilbert_sort, median policy: O(n log n)), kept to compare
// drawings of the two orders (vis_check --geometry=median).
TriangleMesh hilbert_ordered_median(TriangleMesh mesh);

// The position along the Hilbert curve through the 2^21 x 2^21 x 2^21 grid of the cell (x, y, z)
// (each below 2^21): a 63-bit key, by Skilling's transform ("Programming the Hilbert curve", AIP
// Conf. Proc. 707, 2004). Cells with consecutive keys share a face.
std::uint64_t hilbert_key(std::uint32_t x, std::uint32_t y, std::uint32_t z);

// The keys hilbert_ordered sorts by: points quantized to 21 bits an axis in the box of `points`
// (the box of a mesh's positions gives the keys of its order), then hilbert_key.
class HilbertGrid {
public:
    HilbertGrid(const glm::dvec3* points, std::size_t count);
    HilbertGrid(const glm::dvec3& lo, const glm::dvec3& hi);  // the box itself
    std::uint64_t key(const glm::dvec3& p) const;
    // key(points[i]) for i < count into keys[i], many at a time (vectorized).
    void keys(const glm::dvec3* points, std::size_t count, std::uint64_t* keys) const;
    std::uint32_t cell(const glm::dvec3& p, int axis) const;  // the quantized coordinate, < 2^21

private:
    glm::dvec3 lo_{0.0}, scale_{0.0};  // per axis, what maps the box onto [0, 2^21) (0: a flat axis)
};

// The same mesh numbered at random (vertices, faces, and each face's corners rotated: the same
// orientation), from `seed`. For checks that a drawing does not depend on the numbering.
TriangleMesh shuffled_numbering(TriangleMesh mesh, std::uint32_t seed);

}  // namespace inkline
