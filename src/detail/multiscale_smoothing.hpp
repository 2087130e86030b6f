// The smoothed levels' post-pass (multiscale_levels.cpp; docs/detail.md): implicit smoothing of a
// level's positions, (W + t L^order) x = W p with L the mesh's combinatorial (uniform) Laplacian
// and W a per-vertex anchor that spares thin parts (from `thickness`). Internal to src/detail/.
#pragma once

#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "model/topology.hpp"

namespace inkline {

class LevelSmoother {
public:
    explicit LevelSmoother(const MeshTopology& mesh);
    ~LevelSmoother();
    LevelSmoother(const LevelSmoother&) = delete;
    LevelSmoother& operator=(const LevelSmoother&) = delete;

    // Replaces `pos` by the solution of (W + t L^order) x = W pos (order 1 or 2; Eigen's sparse
    // Cholesky), W = diag(anchor) (one weight >= 1 a vertex; empty: the identity): a vertex of
    // weight w is smoothed as with t / w.
    void smooth(double t, int order, const std::vector<double>& anchor, std::vector<glm::dvec3>& pos);

    // Per vertex the shape's thickness there: the distance along the inward vertex normal to the
    // surface on the other side (the shape diameter; a large value where the ray leaves the shape),
    // averaged over the one-ring twice. Embree's rays.
    std::vector<double> thickness(const std::vector<glm::dvec3>& pos) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    const MeshTopology* mesh_;
};

}  // namespace inkline
