#include "detail/temporal_smoothing.hpp"

#include <cmath>

namespace inkline {

double smoothing_weight(double seconds, double frames_per_second, double alpha) {
    const double n = seconds * frames_per_second;
    if (!(n > 1.0)) return 1.0;
    return 1.0 - std::pow(1.0 - alpha, 1.0 / n);
}

void TemporalSmoother::blend(ViewCurvature& now, const std::vector<std::uint32_t>& input_vertex, double weight) {
    ++frame_;
    const float w = float(weight);
    for (std::size_t v = 0; v < input_vertex.size(); ++v) {
        const std::uint32_t i = input_vertex[v];
        if (i >= state_.size()) {
            state_.resize(i + 1, {0.0f, 0.0f, 0.0f});
            seen_.resize(i + 1, UINT32_MAX);  // (never: UINT32_MAX + 1 is no frame)
        }
        std::array<float, 3>& p = state_[i];
        float* q[3] = {&now.ndotv[v], &now.kr[v], &now.dwkr[v]};
        const bool fresh = seen_[i] + 1 != frame_;
        for (int j = 0; j < 3; ++j) {
            p[j] = fresh ? *q[j] : (1.0f - w) * p[j] + w * *q[j];
            *q[j] = p[j];
        }
        seen_[i] = frame_;
    }
}

}  // namespace inkline
