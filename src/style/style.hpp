// Stylization, step 2: what a style file says. Takes a JSON style file (format: styles/README.md)
// and the offset tables and brushes it names; gives a Style. Every unknown key or bad value is an
// inkline::Error "<file>: key '<path>': <problem> (expected ...)".
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/drawing.hpp"
#include "style/offsets.hpp"

namespace inkline {

struct NoiseStyle {
    double normal = 0.0;       // px: amplitude of displacement along the stroke normal
    double tangent = 0.0;      // px: along the stroke tangent
    double wavelength = 40.0;  // px of screen per noise cell (1 / frequency)
    bool active() const { return normal != 0.0 || tangent != 0.0; }
};

enum class WidthRule { Constant, Taper };

struct LineStyle {
    std::uint32_t rgb = 0x000000;
    double opacity = 1.0;
    double width = 1.0;            // times the base width
    WidthRule width_rule = WidthRule::Constant;
    double taper_length = 20.0;    // px at each end (Taper)
    double taper_min = 0.15;       // width at the very ends, as a share of the full width
    // Width factors (need the view's mesh: see style/attributes.hpp): at the nearest and farthest
    // point of the drawing, linear in depth between; at tone 1 (lit) and 0 (dark), linear between.
    double depth_near = 1.0, depth_far = 1.0;
    double light_lit = 1.0, light_dark = 1.0;
    bool uses_attributes() const { return depth_near != 1.0 || depth_far != 1.0 || light_lit != 1.0 || light_dark != 1.0; }
    double dash_on = 0.0, dash_off = 0.0;  // px; 0: solid
    double spacing = 1.5;          // px: resampling of the spine for offsets, noise, outlines
    std::optional<OffsetTable> offsets;
    double offset_scale = 1.0;     // times the table's offsets
    double offset_period = 0.0;    // px; 0: the table's period
    NoiseStyle noise;
    std::string brush;             // PNG path (resolved); empty: no brush
    double brush_aspect = 0.0;     // length / width of one brush image; 0: from the image
    bool omit = false;             // not drawn at all
    // Drawn as plain Cairo strokes, exactly like the default output (no spine processing).
    bool plain() const {
        return !offsets && !noise.active() && brush.empty() && width_rule == WidthRule::Constant && !uses_attributes();
    }
};

struct HatchStyle {
    bool enabled = false;
    double threshold = 0.55;        // Lambertian tone below which strokes are drawn
    bool light_at_camera = true;    // the paper's point light at the eye; else a directional light:
    glm::dvec3 light{0.0, 1.0, 0.0};  // world direction towards the light (unit)
    double length = 0.03;           // world length, as a share of the model's half diagonal
    int segments = 4;               // polyline segments per stroke
    double min_pixels = 3.0;        // strokes shorter on screen are not drawn
    bool by_area = true;            // particles by surface area (even density), else one per triangle centre
    double spacing = 0.015;         // by_area: mean distance between particles, share of the half diagonal
    std::uint32_t seed = 1;
    LineStyle line;                 // how a hatch stroke is drawn
};

struct Style {
    std::string name;
    std::string file;                         // where it was read from ("" for built-ins)
    std::uint32_t background = 0xffffff;
    double base_width = 0.0;                  // px; <= 0: max(1, 1.5 * height / 1024)
    bool draw_hidden = false;                 // hidden lines even without --hidden
    std::vector<LineKind> kinds;              // line kinds the style turns on when the command
                                              // names none (--lines); empty: the command's default
    bool light_at_camera = true;              // light for width_by_light (camera, or a direction:)
    glm::dvec3 light{0.0, 1.0, 0.0};
    bool chain = true;                        // join pieces into strokes
    double max_turn_degrees = 30.0;
    double join_distance = 1e-3;              // px
    bool keep_specks = false;                 // keep lone strokes shorter than a pixel (--keep-specks)
    std::array<LineStyle, kPieceKindCount> lines;  // visible lines, per kind
    // Visible lines of a scene's objects by name (Drawing::object_names): per kind, the style's
    // `lines` with the object's entries over them. An object not named here draws with `lines`.
    std::map<std::string, std::array<LineStyle, kPieceKindCount>> objects;
    // Hidden lines: hidden[k] is for QI k + 1; QI beyond the last entry uses the last one.
    std::vector<LineStyle> hidden;
    HatchStyle hatching;

    // The built-in default: today's look (black, hidden levels 1, 2, >= 3 grey, dashed).
    static Style clean();
    bool uses_attributes() const;  // some line style's width depends on depth or lighting
    const LineStyle& for_qi(LineKind kind, int qi) const;
    // As for_qi, for a line of the object named `object` (null: no object; hidden lines are
    // drawn by QI whatever their object).
    const LineStyle& for_line(LineKind kind, int qi, const std::string* object) const;
};

// Parses a style from JSON text; `file` names it in errors and is the base for relative paths
// (offset tables in <dir>/offsets/NAME.txt, brushes in <dir>/brushes/NAME.png).
Style parse_style(const std::string& json_text, const std::string& file);
// Reads a style file.
Style load_style_file(const std::string& path);
// NAME (looked up as NAME.json in styles_dir()) or a FILE (a path with '/' or ending in .json).
Style load_style(const std::string& name_or_file);
// The same with NAME looked up in `dir` (a program built against the installed library).
Style load_style(const std::string& name_or_file, const std::string& dir);
// Where style names are found: $INKLINE_STYLES if set, else the styles installed with the running
// program, <its directory>/../share/inkline/styles (the build tree links that to the source's styles/).
std::string styles_dir();

}  // namespace inkline
