// A Drawing's pieces as triangles for the GPU: every segment a quad around the line, one pixel
// wider than the stroke on each side for antialiasing, carrying the distance along the piece (for
// dashes) and a style (visible, or hidden by QI level: grey, dashed, thinner, as the writers draw
// them). No GL here: the window uploads the vertices as they are.
#pragma once

#include <array>

#include <vector>

#include "core/drawing.hpp"

namespace inkline {

struct LineVertex {
    float x, y;      // pixels, DESIGN.md convention (origin top-left, y down)
    float across;    // signed distance from the centre line, pixels
    float along;     // arc length from the start of the piece, pixels
    float half;      // half the stroke width, pixels
    float style;     // 0 visible, 1 QI 1, 2 QI 2, 3 QI >= 3
    float u;         // along the segment from its start, pixels (< 0 or > length: in a cap)
    float length;    // the segment's length, pixels (caps and joins are round: coverage by the
                     // distance to the segment, and overlaps blend by the minimum)
};

struct LineStyleGl {
    float grey;        // 0 black .. 1 white
    float width_scale;
    float dash_on, dash_off;  // pixels; dash_on == 0: solid
};
// Indexed by LineVertex::style; the same looks as the SVG/PDF/PNG writers.
const LineStyleGl& line_style(int style);

struct LineMeshOptions {
    bool hidden = false;               // hidden pieces too
    std::array<bool, kPieceKindCount> kinds = all_kinds();  // by LineKind: which are drawn
    static std::array<bool, kPieceKindCount> all_kinds() {
        std::array<bool, kPieceKindCount> k;
        k.fill(true);
        return k;
    }
    double width = 0.0;                // visible stroke width in px; <= 0: max(1, 1.5 * height / 1024)
    double simplify_px = 0.0;          // > 0: drop points within this many pixels of the line kept
};

// Replaces `out` with the quads of every drawn piece (6 vertices per segment); hidden styles come
// first so visible lines are drawn over them. Pieces with a non-finite point are skipped.
void build_line_mesh(const Drawing& drawing, const LineMeshOptions& options, std::vector<LineVertex>& out);

}  // namespace inkline
