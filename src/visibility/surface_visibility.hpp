// Visibility of curves that run across faces (suggestive contours, smooth contours, ridges,
// valleys: curvature/curvature.hpp's SurfaceCurves). Takes the view's features (their silhouette
// and border edges occlude), the curves and the camera; gives pieces in pixels with their QI.
// Each curve is clipped at the near plane, projected, and cut wherever its image crosses the image
// of a silhouette or border edge. QI then comes from the same machinery as the mesh curves':
// - reference: one ray test per piece (RayCaster::count_layers, exact);
// - propagation: one ray test per curve (at its longest piece), then along the curve the change of
//   QI at each crossing (crossing_delta: +-2 behind a silhouette, +-1 behind a border, 0 where the
//   occluder lies behind the curve), and +-1 where the curve itself passes over a silhouette edge
//   into the fold behind (or in front of) its own sheet. Curves on self-intersecting faces, and
//   any curve whose propagated QI would go negative (a non-generic view), take the reference.
// Intersection curves (model/intersection_curves.hpp) take the same path with two faces per
// segment, one of each surface: the point lies on both, so neither counts in its QI (the ray test
// skips both, as a silhouette edge's skips its two faces), neither's edges occlude it, and it
// passes over a fold of either surface (+-1 each); a run also ends where the curve passes through
// a third surface (IntersectionCurves::point_cut: QI changes there with no event in the image).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "curvature/curvature.hpp"
#include "features/features.hpp"
#include "model/intersection_curves.hpp"
#include "model/topology.hpp"
#include "visibility/crossings.hpp"
#include "visibility/ray_caster.hpp"

namespace inkline {

struct SurfaceVisibilityOptions {
    bool propagate = true;  // false: a ray test per piece (the reference)
    // Per face: intersects another face (Model::pierced_faces); null: none is.
    const std::vector<std::uint8_t>* pierced_faces = nullptr;
    // Added to each piece's Piece::curve, so pieces of surface curves do not share curve numbers
    // with the feature curves of the same drawing.
    std::uint32_t curve_offset = 0;
};

struct SurfaceVisibilityStats {
    std::size_t pieces = 0, crossings = 0, ray_tests = 0;
    std::size_t fallbacks = 0;  // curves that took the reference (pierced faces, inconsistent QI)
};

// Storage reused from view to view (no allocation once a view as large has been seen).
struct SurfaceVisibilityScratch {
    std::vector<Segment2> occluders;
    SegmentGrid grid;
    struct Crossing {
        std::uint32_t seg;      // position of the segment in the run
        double t;               // along the segment's image
        std::uint32_t edge;     // occluding mesh edge
        // Nonzero where the curve itself passes over a silhouette edge, from a face to its
        // neighbour of the other facing: the change of QI there (+-1), else 0 (an occluder).
        int fold;
    };
    std::vector<Crossing> crossings;
    struct RunSegment {
        glm::dvec3 A, B;        // clipped to the near plane, in travel order
        glm::dvec2 a, b;        // their images
        std::uint32_t face;
        std::uint32_t face2;    // intersection curves: the other surface's face; else kNoFace
    };
    std::vector<RunSegment> run;
    std::vector<int> qi;
    std::vector<std::uint32_t> first_piece;  // per run piece: index into out
};

// Appends the pieces of `curves` (visible and hidden, QI set) to `out`. `rays` is called only when
// a ray test is needed (it may build the index).
SurfaceVisibilityStats surface_visibility(const MeshTopology& mesh, const Features& features, const Camera& camera,
                                          const SurfaceCurves& curves,
                                          const std::function<const RayCaster&()>& rays,
                                          const SurfaceVisibilityOptions& options, SurfaceVisibilityScratch& scratch,
                                          std::vector<Piece>& out);

// The same for the intersection curves of the model (pieces of kind LineKind::Intersection);
// options.pierced_faces is not used (see above).
SurfaceVisibilityStats intersection_visibility(const MeshTopology& mesh, const Features& features,
                                               const Camera& camera, const IntersectionCurves& curves,
                                               const std::function<const RayCaster&()>& rays,
                                               const SurfaceVisibilityOptions& options,
                                               SurfaceVisibilityScratch& scratch, std::vector<Piece>& out);

}  // namespace inkline
