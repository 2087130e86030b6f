// The self-intersection search (self_intersections.hpp) started before the topology exists, so
// that it runs beside the topology's construction: it needs only the faces and their corners,
// which build_topology keeps as they are (the same face numbers, corners and positions, in the
// same buffers). Model::load uses it when it may use more threads (LoadOptions::threads); the
// result is the same as self_intersections(topology, threads).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>

#include <glm/vec3.hpp>

#include "model/self_intersections.hpp"

namespace inkline {

// The arrays the search reads: face_count triangles of corner indices into vertex_count positions.
// Read in place, not copied (a copy was 24 bytes a vertex and 12 a face more at a big load's
// peak): they must stay alive and unchanged until finish() returns or the search is destroyed.
struct SearchInput {
    const glm::dvec3* positions = nullptr;
    const std::array<std::uint32_t, 3>* faces = nullptr;
    std::size_t face_count = 0;
    std::size_t vertex_count = 0;
};

class EarlySelfIntersections {
public:
    // Starts the search on a thread of its own (and up to threads - 2 more, as the search's size
    // allows).
    EarlySelfIntersections(const SearchInput& input, int threads);
    // Stops the search (its threads return at their next step: a task, or a stage of its
    // preparation) and waits for them; from then on the arrays are no longer read.
    ~EarlySelfIntersections();
    EarlySelfIntersections(const EarlySelfIntersections&) = delete;
    EarlySelfIntersections& operator=(const EarlySelfIntersections&) = delete;
    // Takes the search's remaining tasks on the calling thread, waits for the others, and gives
    // the result on `mesh`, whose faces and positions are the ones given. Once only.
    SelfIntersections finish(const MeshTopology& mesh);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace inkline
