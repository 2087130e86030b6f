// What the two progressive-mesh test files share: armadillo's hierarchy, built once a test
// program (a second or so), a session's options with geomorphs, and the criterion at a target
// size in pixels.
#pragma once

#include "detail/progressive_mesh.hpp"
#include "detail/progressive_mesh_session.hpp"
#include "model/mesh_io.hpp"
#include "test_data.hpp"

namespace inkline::test {

inline const ProgressiveMesh& armadillo_pm() {
    static const ProgressiveMesh pm(load_mesh(mesh_path("armadillo")));
    return pm;
}

// A session at 3 px with geomorphs, for an input known to be embedded (armadillo, bunny00).
inline PmViewOptions geomorphs_at_3px() {
    PmViewOptions o;
    o.target_px = 3.0;
    o.geomorphs.enabled = true;
    o.input_self_intersects = false;
    return o;
}

inline DetailCriterion target_px(double px) {
    DetailCriterion c;
    c.target_area_px = px * px;
    return c;
}

}  // namespace inkline::test
