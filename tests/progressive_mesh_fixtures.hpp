// What the two progressive-mesh test files share: armadillo's hierarchy, built once a test
// program (a second or so), and the criterion at a target size in pixels.
#pragma once

#include "detail/progressive_mesh.hpp"
#include "model/mesh_io.hpp"
#include "test_data.hpp"

namespace inkline::test {

inline const ProgressiveMesh& armadillo_pm() {
    static const ProgressiveMesh pm(load_mesh(mesh_path("armadillo")));
    return pm;
}

inline DetailCriterion target_px(double px) {
    DetailCriterion c;
    c.target_area_px = px * px;
    return c;
}

}  // namespace inkline::test
