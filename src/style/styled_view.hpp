// A view's drawing, stylized: hatching (if the style asks for it, with ray tests against the
// model), depth and tone at the points (if the style's widths use them), then stylize(). What
// `inkline render --style` writes and what `inkline view` shows with a style.
#pragma once

#include "core/camera.hpp"
#include "pipeline.hpp"
#include "style/hatching.hpp"
#include "style/stylize.hpp"

namespace inkline {

struct StyledViewStats {
    StylizeStats stylize;
    HatchStats hatching;
};

// `hidden`: hidden lines were asked for (--hidden); the style may draw them anyway.
StyledDrawing stylize_view(const Model& model, const Camera& camera, const View& view, const Style& style,
                           bool hidden, StyledViewStats* stats = nullptr);

}  // namespace inkline
