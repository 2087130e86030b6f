// Visibility, fast method (`--visibility=fast`, issue 46): visible lines only, with a bounded
// error against the exact method (appel.hpp). Takes MeshTopology + Features + Camera (+ the
// ray-test index, built only if a sample needs it); gives the curves split into visible (qi 0)
// and hidden (qi 1: "at least one layer", not the exact QI) pieces, with their spans.
//
// How: a coarse depth buffer (depth_buffer.hpp) of the faces that can be nearest, then samples
// along every curve about one buffer pixel apart. A sample is settled by the buffer only when the
// pixel centres around it agree: every one clearly in front of it (hidden) or none (visible),
// where "clearly" means beyond a depth margin of a few buffer pixels' size, the sample's own
// faces and the faces around its edge never count as in front, silhouettes look only at centres
// on their outer side (their own surface folds away on the inner side), and creases compare with
// their own faces' planes. Everything else is ambiguous and takes an exact ray test: samples near
// cusps (the surface hides itself there), on faces that pierce other faces, and wherever the
// centres disagree (near an occluder's outline). Edges on back faces of a closed solid seen from
// outside, and concave silhouettes there, are hidden without a look (parity). Visibility changes
// between two samples are placed halfway: the pieces' ends are within half a sample spacing of
// the exact ones. What stays wrong is what the buffer settles wrongly: occluders thinner than a
// buffer pixel, and surfaces within the margin of each other away from cusps;
// bench/results/fast_visibility.md measures it.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "features/features.hpp"
#include "model/topology.hpp"
#include "visibility/depth_buffer.hpp"
#include "visibility/ray_caster.hpp"
#include "visibility/visibility.hpp"

namespace inkline {

struct FastVisibilityOptions {
    // Long side of the depth buffer in pixels (the image's aspect); 0: the image's own size.
    int buffer_px = 768;
    // Depth margin, in buffer pixels' world size at the sample: nearer than that is "in front".
    double margin_px = 2.0;
    // Samples within this image distance (pixels along the curve) of a cusp take the state of the
    // samples beyond it on their side (the surface hides itself there at depths too close for the
    // buffer).
    double cusp_px = 3.0;
    // Runs of at most this many ambiguous samples take their centres' majority; longer runs a ray
    // test each.
    std::size_t short_run = 4;
    // Stretches near cusps with no settled sample beside them on their side (short curves between
    // cusps): a ray test each (true) or the buffer's own verdict (false).
    bool exact_lone_cusps = false;
    // Per face: pierces another face (model/self_intersections.hpp); null: none does.
    const std::vector<std::uint8_t>* pierced_faces = nullptr;
};

struct FastVisibilityStats {
    bool exact_needed = false;  // a face reaches the near plane: nothing was decided
    std::size_t samples = 0, ambiguous = 0, ray_tests = 0, faces_drawn = 0;
    double seconds_buffer = 0.0, seconds_samples = 0.0, seconds_ray_tests = 0.0;
};

// The fast method's storage, kept from view to view.
class FastVisibility {
public:
    // Pieces of the curves of the kinds `kinds` wants, in curve order, into `pieces` and `spans`
    // (cleared first). When stats.exact_needed is set they are left empty.
    FastVisibilityStats run(const MeshTopology& mesh, const Features& features, const Camera& camera,
                            const std::function<const RayCaster&()>& rays, const FeatureOptions& kinds,
                            const FastVisibilityOptions& options, std::vector<Piece>& pieces,
                            std::vector<std::vector<EdgeSpan>>& spans);
    const DepthBuffer& buffer() const { return buffer_; }

    struct Scratch;  // one curve's samples and edges (fast_visibility.cpp)

private:
    DepthBuffer buffer_;
    std::vector<std::uint8_t> draw_;  // per face: drawn into the buffer
    std::vector<std::uint8_t> cusp_;  // per vertex: a cusp of this view (cleared after it)
    std::shared_ptr<Scratch> scratch_;
};

}  // namespace inkline
