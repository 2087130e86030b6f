#include "style/styled_view.hpp"

#include <optional>

#include "style/attributes.hpp"
#include "visibility/visibility.hpp"

namespace inkline {

StyledDrawing stylize_view(const Model& model, const Camera& camera, const View& view, const Style& style,
                           bool hidden, StyledViewStats* stats) {
    std::vector<std::vector<glm::dvec2>> hatches;
    if (style.hatching.enabled) {
        Camera hc = camera;
        if (hc.near_distance() <= 0.0) hc.set_near(default_near(model.topology()));
        for (auto& h : hatch_strokes(model.topology(), hc, model.rays(), style.hatching, true,
                                     stats ? &stats->hatching : nullptr))
            hatches.push_back(std::move(h.points));
    }
    std::optional<PointAttributes> attributes;
    if (style.uses_attributes())
        attributes = point_attributes(model.topology(), camera, view.drawing, view.spans, style.light_at_camera,
                                      style.light);
    return stylize(view.drawing, style, hidden, hatches, stats ? &stats->stylize : nullptr,
                   attributes ? &*attributes : nullptr);
}

}  // namespace inkline
