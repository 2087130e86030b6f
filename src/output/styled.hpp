// Output of stylized drawings (style/stylize.hpp): SVG, PDF and PNG drawn by Cairo (its SVG
// surface for SVG, so brush textures come out the same in all three), written atomically.
#pragma once

#include <string>

#include "output/writers.hpp"
#include "style/stylize.hpp"

namespace inkline {

// SVG, PDF or PNG as bytes. Throws inkline::Error for JSON (stylized output has no JSON form;
// JSON keeps the exact pieces) and when a brush image cannot be read.
std::string styled_to_bytes(const StyledDrawing& drawing, Format format);
// Throws inkline::Error(path, reason) on failure; the target is then left untouched.
void write_styled(const StyledDrawing& drawing, const std::string& path, Format format);

}  // namespace inkline
