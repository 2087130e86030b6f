#include "core/drawing.hpp"

namespace inkline {

const char* to_string(LineKind k) {
    switch (k) {
        case LineKind::Silhouette: return "silhouette";
        case LineKind::Border: return "border";
        case LineKind::Crease: return "crease";
        case LineKind::Freeform: return "freeform";
        case LineKind::Suggestive: return "suggestive";
        case LineKind::SmoothContour: return "smooth-contour";
        case LineKind::Ridge: return "ridge";
        case LineKind::Valley: return "valley";
        case LineKind::Intersection: return "intersection";
        case LineKind::ToneDark: return "tone-dark";
        case LineKind::ToneHighlight: return "tone-highlight";
    }
    return "unknown";
}

double kind_width(LineKind k) {
    switch (k) {
        case LineKind::Freeform: return 0.5;
        case LineKind::Suggestive:
        case LineKind::Ridge:
        case LineKind::Valley: return 0.7;
        default: return 1.0;
    }
}

std::uint32_t kind_rgb(LineKind k) { return k == LineKind::ToneHighlight ? 0xffffff : 0x000000; }

bool parse_line_kind(const std::string& s, LineKind& out) {
    for (int i = 0; i < kLineKindCount; ++i) {
        if (s == to_string(LineKind(i))) {
            out = LineKind(i);
            return true;
        }
    }
    return false;
}

}  // namespace inkline
