// QI by propagation (Markosian et al. 97, sections 4.2-4.5): the fast visibility.
// Takes the pieces of the view with the links between them (where a curve crosses behind an
// occluding edge, where curves meet at a vertex); gives every piece its QI from a base QI per
// cluster, fixed by the bounding-box rule, lower bound and parity, constraints between clusters,
// and ray tests only for what stays unknown (counted).
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "core/camera.hpp"
#include "features/features.hpp"
#include "model/topology.hpp"
#include "visibility/ray_caster.hpp"
#include "visibility/visibility.hpp"

namespace inkline {

struct AppelOptions {
    // Totally occluded clusters get their exact QI (a ray test each) only when hidden lines are
    // drawn; otherwise their lower bound (> 0) is enough to leave them out.
    bool exact_hidden = true;
    // Per face: intersects another face (model/self_intersections.hpp). Pieces on such a face get
    // a ray test each and are kept out of propagation: passing through a face changes QI unseen.
    // Null where no face is flagged (Model::pierced_faces): the pieces' faces are not looked up.
    const std::vector<std::uint8_t>* pierced_faces = nullptr;
    // Walk the surface (section 4.4) before falling back to a ray test.
    bool walk = true;
    // With 2 or more: the crossings' QI changes, the local occlusion at curve ends and the walks
    // of a large view split among up to this many threads (the same results).
    int threads = 1;
};

struct AppelStats {
    std::size_t clusters = 0;
    std::size_t clusters_bbox = 0;      // fixed by the bounding-box rule
    std::size_t clusters_occluded = 0;  // proved totally occluded by lower bound, parity, constraints, walks
    std::size_t clusters_bounded = 0;   // decided by upper bounds from decided clusters (no walk, no ray)
    std::size_t ray_tests = 0;
    std::size_t walks = 0;
    std::size_t inconsistent = 0;       // clusters whose propagated offsets contradict (non-generic views)
    std::size_t pierced = 0;            // pieces on self-intersecting faces
    // Wall time of the walks (with the occluders' grid they search, built for them; on several
    // threads when there are several: all at once) and of the ray tests (the ray-test index's
    // construction, once per model, not included); the rest of assign_qi_appel's time is
    // propagation.
    double seconds_walks = 0.0;
    double seconds_ray_tests = 0.0;
};

// Local change of QI at a vertex: the number of faces around `vertex` (other than the faces of
// `edge`) that hide the points of `edge` infinitesimally close to the vertex. Exact predicates.
// `face_front` is the view's facing (Features::face_front).
int local_occlusion(const MeshTopology& mesh, const Camera& camera, const FaceFacing& face_front,
                    std::uint32_t vertex, std::uint32_t edge);

// Change of QI of a curve going from c1 to c2 (its segment, in 3D) behind occluding edge `occluder`
// (silhouette: +-2, border: +-1), or 0 when the occluder is not in front of the curve there.
int crossing_delta(const MeshTopology& mesh, const Camera& camera, std::uint32_t occluder, const glm::dvec3& c1,
                   const glm::dvec3& c2);

// Assigns pieces[i].qi for every piece of `graph`.
// `rays` gives the ray-test index, called only if a ray test is needed (it may build it).
AppelStats assign_qi_appel(const MeshTopology& mesh, const Camera& camera, const FaceFacing& face_front,
                           const std::function<const RayCaster&()>& rays, PieceGraph& graph,
                           const AppelOptions& options = {});

}  // namespace inkline
