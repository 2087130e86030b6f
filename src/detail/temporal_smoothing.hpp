// Temporal smoothing of per-vertex view quantities (seed 000, section 3.3): instead of replacing
// last frame's value p with this frame's q, p <- (1 - w) p + w q, so suggestive contours extracted
// from an adaptive mesh (whose connectivity, hence curvature, changes by steps) do not pop.
//
// Takes: this frame's ViewCurvature of the adapted mesh and each adapted vertex's input index.
// Gives: the same quantities smoothed per input vertex (n . v, the stand-in for the normal used by
// the surface lines; k_r; D_w k_r). Silhouettes of the mesh are not smoothed: inkline finds them
// exactly from the faces, whose motion the geomorphs already make continuous.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "curvature/curvature.hpp"

namespace inkline {

// The weight that brings a value a share `alpha` of the way to a fixed target in `seconds` at
// `frames_per_second`: n = f t frames, (1 - w)^n = 1 - alpha, so w = 1 - (1 - alpha)^(1/n).
// (t = 0.8 s, f = 25, alpha = 0.9: w = 0.1087, the seed's example.) 1 when n <= 1.
double smoothing_weight(double seconds, double frames_per_second, double alpha);

class TemporalSmoother {
public:
    // Blends `now` (per adapted vertex) into the state kept per input vertex and writes the result
    // back into `now`. A vertex not seen the frame before (new, or back after a collapse) starts
    // from its value now: its old state belongs to another shape.
    void blend(ViewCurvature& now, const std::vector<std::uint32_t>& input_vertex, double weight);
    void reset() { state_.clear(), seen_.clear(), frame_ = 0; }

private:
    std::vector<std::array<float, 3>> state_;  // n . v, k_r, D_w k_r
    std::vector<std::uint32_t> seen_;          // the frame each input vertex was last blended in
    std::uint32_t frame_ = 0;
};

}  // namespace inkline
