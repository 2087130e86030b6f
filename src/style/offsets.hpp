// Offset tables (Markosian et al. 97, section 5): vector offsets in the tangent-normal basis of a
// stroke, q(t) = p(t) + v_x(t) p'(t) + v_y(t) n(t), repeated along the stroke with a period,
// with "break" tags that leave adjacent vertices unconnected (dashes, circles, letters).
// Text format (styles/README.md):
//     # comment                      anything after '#' is ignored
//     period 12                      px of stroke per repetition (required, >= 0.1)
//     t vx vy                        one vertex: t in [0, 1], non-decreasing; vx, vy in px
//     break                          no line from the previous vertex to the next one
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

namespace inkline {

class ArcPolyline;

struct OffsetTable {
    struct Vertex {
        double t = 0.0, vx = 0.0, vy = 0.0;
        bool break_before = false;  // not connected to the previous vertex
    };
    std::string name;
    double period = 0.0;
    std::vector<Vertex> vertices;
};

// Bounds that keep a valid table from making strokes of millions of points (found by fuzz/run.sh
// offsets): offsets within +-1000 px, at most 1000 vertices, at most 100 vertices per px of
// period (also checked against a style's period override).
inline constexpr double kMaxOffsetPx = 1000;
inline constexpr std::size_t kMaxOffsetVertices = 1000;
inline constexpr double kMaxOffsetVerticesPerPx = 100;

// Throws inkline::Error("<file>:<line>", problem) on a malformed table.
OffsetTable parse_offset_table(const std::string& text, const std::string& file);
OffsetTable load_offset_table(const std::string& path);

// Applies the table along a spine: the table repeated every `period` px (table period when
// period <= 0) from arc length 0, offsets times `scale`, with extra vertices every `spacing` px
// between table vertices so the result follows the spine's curvature. Breaks (and the seam of
// a table that does not start where it ends connected) split the result into runs. Each output
// vertex also gives the arc length of the spine point it offsets (for width rules).
struct OffsetRun {
    std::vector<glm::dvec2> points;
    std::vector<double> arc;  // spine arc length per point
};
std::vector<OffsetRun> apply_offsets(const ArcPolyline& spine, const OffsetTable& table, double scale,
                                     double period, double spacing);

}  // namespace inkline
