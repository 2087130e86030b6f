// Stylization, the stage's front: takes a Drawing, a Style and (optionally) hatching strokes;
// gives a StyledDrawing: layers of marks (plain Cairo strokes, filled outlines of variable width,
// brush-textured quads) that output/ draws to SVG, PDF and PNG.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "core/drawing.hpp"
#include "style/strokes.hpp"
#include "style/style.hpp"

namespace inkline {

// A brush image mapped onto one quad of a stroke: corners in order start-left, start-right,
// end-right, end-left; the brush's x runs from u0 to u1 (shares of the image width) from the
// start crossbar to the end one, its y across the stroke.
struct BrushQuad {
    glm::dvec2 corner[4];
    double u0 = 0.0, u1 = 1.0;
};

struct Mark {
    enum class Type { Stroke, Fill, Brush };
    Type type = Type::Stroke;
    std::uint32_t rgb = 0;
    double opacity = 1.0;
    double width = 1.0;                  // Stroke: px
    double dash_on = 0.0, dash_off = 0.0;
    std::vector<std::vector<glm::dvec2>> paths;  // Stroke: open polylines; Fill: closed outlines
    std::string brush;                   // Brush: PNG path
    std::vector<BrushQuad> quads;        // Brush
    std::uint32_t object = 0;            // index in StyledDrawing::object_names
};

struct StyledLayer {
    std::string id;  // "<kind>-visible", "<kind>-hidden-qi<N>", "hatching"
    std::vector<Mark> marks;
};

struct StyledDrawing {
    int width = 0, height = 0;
    std::uint32_t background = 0xffffff;
    RasterLayer base;                 // over the background, under the layers (Drawing::base)
    std::vector<StyledLayer> layers;  // in drawing order
    std::vector<std::string> object_names;  // Drawing::object_names (several: a group per object)
};

struct StylizeStats {
    std::size_t strokes = 0, points = 0, hatches = 0;
    std::size_t specks_dropped = 0;  // pieces left out as specks (ChainStats)
};

// `hidden`: --hidden was given (hidden lines are drawn when it is or when the style says so).
// `hatches`: screen polylines of shading strokes (style/hatching.hpp), drawn below visible lines.
// `attributes`: depth and tone per piece point (style/attributes.hpp), for widths by depth or
// lighting; without them those factors are 1.
StyledDrawing stylize(const Drawing& drawing, const Style& style, bool hidden,
                      const std::vector<std::vector<glm::dvec2>>& hatches = {}, StylizeStats* stats = nullptr,
                      const PointAttributes* attributes = nullptr);

// A stroke's opacity from its pieces' per-point opacity (tone lines): their mean, in steps of 1/8.
double stroke_opacity(const Drawing& drawing, const Stroke& stroke);

// The outline of a stroke of variable width: left side forward, right side back, closed (the
// first point repeated at the end). widths[i] is the full width at points[i].
std::vector<glm::dvec2> width_outline(const std::vector<glm::dvec2>& points, const std::vector<double>& widths);

// Base width in px of a drawing of this height for this style (max(1, 1.5 * height / 1024) unless set).
double base_width(const Style& style, int height);

}  // namespace inkline
