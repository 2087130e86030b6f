// Output of stylized drawings (style/stylize.hpp): PDF and PNG drawn by Cairo; SVG written by hand
// with one Inkscape layer per StyledLayer (as the default writer: "<kind>-visible",
// "<kind>-hidden-qi1", ..., "hatching") and brush strokes as the brush image (embedded once)
// mapped onto each quad through a clipping viewport. Written atomically.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "output/writers.hpp"
#include "style/stylize.hpp"

namespace inkline {

// SVG, PDF or PNG as bytes. Throws inkline::Error for JSON (stylized output has no JSON form;
// JSON keeps the exact pieces) and when a brush image cannot be read.
std::string styled_to_bytes(const StyledDrawing& drawing, Format format);
// The drawing as a PNG would show it, in memory: width*height pixels, row by row from the top,
// each 0x00RRGGBB (Cairo's RGB24, the upper byte unused). For the preview window's texture.
void styled_to_pixels(const StyledDrawing& drawing, std::vector<std::uint32_t>& pixels);
// Throws inkline::Error(path, reason) on failure; the target is then left untouched.
void write_styled(const StyledDrawing& drawing, const std::string& path, Format format);

}  // namespace inkline
