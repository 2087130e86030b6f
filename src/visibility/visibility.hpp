// Visibility, reference method: curves are projected, split at every image-space crossing with
// a silhouette or border edge (and where the near plane cuts them), and every piece gets its QI
// from one ray test at a point inside it. Takes MeshTopology + Features + Camera + RayCaster;
// gives pieces in pixels with QI, and where each piece lies on the mesh edges.
#pragma once

#include <cstdint>
#include <vector>

#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "features/features.hpp"
#include "model/topology.hpp"
#include "visibility/ray_caster.hpp"

namespace inkline {

// A stretch of one mesh edge: parameters along the edge from edge_vertex[edge][0] (0) to [1] (1).
struct EdgeSpan {
    std::uint32_t edge;
    double s0, s1;
};

struct VisibleCurves {
    std::vector<Piece> pieces;
    std::vector<std::vector<EdgeSpan>> spans;  // parallel to pieces
    std::size_t crossings = 0;                 // intersecting (curve edge, occluding edge) pairs
    std::size_t ray_tests = 0;
};

// Default near plane of a camera for this model: 1e-6 of the model's half diagonal in front of
// the eye plane (geometry closer than that is clipped, as in any graphics pipeline).
double default_near(const MeshTopology& mesh);

VisibleCurves compute_visibility(const MeshTopology& mesh, const Features& features, const Camera& camera,
                                 const RayCaster& rays);

}  // namespace inkline
