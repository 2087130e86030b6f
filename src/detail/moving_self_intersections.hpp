// The self-intersections of a mesh of which only some vertices have moved off an embedded state:
// the progressive mesh's frame, whose geomorphs slide vertices between their own position and
// their parent's (a split's faces cross their neighbours while its vertex slides out).
//
// Takes: the mesh and, per vertex, whether it moved (its shown position is not its own). The
// mesh with every vertex at its own position is taken to be embedded (the compromise of
// PmViewOptions::input_self_intersects), so every intersecting pair has a face with a moved
// corner: such a pair is found by testing only those "moving" faces against every face, not the
// whole mesh against itself. Gives: the SelfIntersections that self_intersections(mesh) gives
// under that assumption, flags and cuts bit for bit (tests/test_progressive_mesh.cpp checks the
// flags and the drawings against the full search); the pairs are the same set in another order
// (intersection lines chain them in the full search's order: a view that draws them takes the
// full search).
//
// How: the moving faces' boxes in a uniform grid, every face's box streamed through it
// (O(faces + candidate pairs)); the candidates copied into a small mesh (same order, same
// corners) and searched by the model's own exact search (model/self_intersections.hpp) for their
// flags only; then the flagged faces (both faces of a pair are flagged), with the faces across
// their edges so that each keeps its edges' orientation and neighbours (the cuts depend on them),
// searched again for the pairs and cuts; the results mapped back. Most of the cost is the exact
// predicates and cut constructions on the moving faces (slivers early in a split's morph), so it
// follows the number of moving faces, which a steady inward dolly makes a large share of the mesh
// (docs/progressive_mesh.md, Benchmarks).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "model/self_intersections.hpp"

namespace inkline {

struct MovingSearchStats {
    std::size_t moving_faces = 0;     // faces with a moved corner
    std::size_t candidate_faces = 0;  // faces whose box meets a moving face's box (moving ones included)
    std::size_t searched_faces = 0;   // the faces flagged among them and the faces across their edges
};

SelfIntersections self_intersections_of_moving(const MeshTopology& mesh, const std::vector<std::uint8_t>& moved_vertex,
                                               MovingSearchStats* stats = nullptr);

}  // namespace inkline
