// Intersection curves: where two surfaces of the model cross (two objects pressed into each other,
// a self-intersecting mesh). They do not depend on the view, so they are built once per model
// (Model::intersection_curves), and only when intersection lines are drawn.
// Takes the mesh and its intersecting face pairs (SelfIntersections::pairs, found by the exact
// search of self_intersections.hpp); gives the crossing curves as polylines in world coordinates,
// each segment lying on two faces, one of each surface.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "model/topology.hpp"

namespace inkline {

struct IntersectionCurves {
    struct Curve {
        std::uint32_t begin, end;  // points [begin, end)
        bool closed;               // a loop: last point == first point
        // The curve passes through a third surface (a face of it holds a segment of another
        // intersection curve, or of itself, that crosses its own): its QI can change there with
        // no event in the image. Visibility cuts it at those points (point_cut).
        bool meets_other;
        // Such a meeting could not be located (segments that overlap along a line): its
        // visibility takes a ray test per piece.
        bool reference;
    };
    std::vector<Curve> curves;
    std::vector<glm::dvec3> points;
    // Per point i, the two faces the segment from point i to i + 1 lies on ({kNoFace, kNoFace} at
    // a curve's last point). Along a curve slot 0 stays on one surface and slot 1 on the other
    // while the curve passes from face to face across edges.
    std::vector<std::array<std::uint32_t, 2>> segment_faces;
    // Per point: 1 where the curve passes through a third surface (a triple point; never a
    // curve's first or last point).
    std::vector<std::uint8_t> point_cut;
    // Intersecting pairs that gave no segment: coplanar (overlapping faces lie on one another:
    // no crossing to draw) or meeting at a single point (touching).
    std::size_t coplanar_pairs = 0, point_pairs = 0;
};

// The crossing curves of the faces in `pairs` (each pair: two faces that intersect, not only at
// a shared edge or vertex). A segment per non-coplanar pair: its ends are where an edge of one face
// passes through the other, decided by exact predicates (CGAL) and named by that (edge, face), so
// that the next pair along the curve, which meets the same edge, names the same point and the
// segments chain by name, not by rounded coordinates. Ends that coincide under other names
// (an edge through an edge or a vertex) are joined within 1e-9 of the model's size.
IntersectionCurves intersection_curves(const MeshTopology& mesh,
                                       const std::vector<std::array<std::uint32_t, 2>>& pairs);

}  // namespace inkline
