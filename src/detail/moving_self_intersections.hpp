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
// How: the moving faces' boxes in a uniform grid, every face's box streamed through it, each pair
// of a moving face and a face whose box meets its own listed once (O(faces + candidate pairs));
// those pairs tested exactly and the cuts of the intersecting ones constructed on the mesh itself,
// by the model's own search (model/self_intersections.hpp: self_intersections_among), so that they
// are the full search's bit for bit. Pairs of two unmoved faces are never tested: where the mesh
// at its own positions is not embedded after all (a coarse front's faces can cut into each other),
// such a pair is missed, as the earlier search of the candidates' submesh missed those away from
// moving faces (docs/progressive_mesh.md: measured, and what would find them). The cost follows
// the number of moving faces (about 13 candidate pairs each, mostly the faces around their
// corners), which a steady inward dolly makes a large share of the mesh (docs/progressive_mesh.md,
// Benchmarks).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "model/self_intersections.hpp"

namespace inkline {

struct MovingSearchStats {
    std::size_t moving_faces = 0;     // faces with a moved corner
    std::size_t candidate_faces = 0;  // faces whose box meets a moving face's box (moving ones included)
    std::size_t candidate_pairs = 0;  // pairs of a moving face and a face whose box meets its own, tested exactly
};

SelfIntersections self_intersections_of_moving(const MeshTopology& mesh, const std::vector<std::uint8_t>& moved_vertex,
                                               MovingSearchStats* stats = nullptr);

}  // namespace inkline
