// The result of one view: every curve piece with its QI, in pixels, plus statistics.
// This is what output/ writes (SVG, PDF, PNG, JSON) and what tests compare.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "core/camera.hpp"

namespace inkline {

// Freeform: line-art strokes on freeform surfaces (src/freeform/), not a feature of the mesh.
// Suggestive .. Valley: curves across faces from the mesh's curvature (src/curvature/), not along
// mesh edges. Intersection: where two surfaces of the model cross (model/intersection_curves.hpp).
enum class LineKind : std::uint8_t {
    Silhouette = 0, Border = 1, Crease = 2, Freeform = 3,
    Suggestive = 4, SmoothContour = 5, Ridge = 6, Valley = 7,
    // Where two surfaces cross (features/intersections): curves on two faces at once.
    Intersection = 8,
    // Lines of the tone image (src/tone/): dark lines in valleys, light lines on ridges of tone.
    ToneDark = 9, ToneHighlight = 10,
};
inline constexpr int kLineKindCount = 3;   // kinds of mesh feature curves (features/ chains these)
inline constexpr int kPieceKindCount = 11;  // every kind a Drawing can hold (writers draw these)
const char* to_string(LineKind k);
// Width of a kind's lines as a share of the outline's, in every writer and the window: freeform
// strokes are hatching, and lines from curvature suggest shape inside the outline, so both are
// drawn lighter than the lines around them.
double kind_width(LineKind k);
// Colour of a kind's visible lines in the default look (0xRRGGBB): black, but highlight lines,
// which are drawn light over the base coat.
std::uint32_t kind_rgb(LineKind k);
// Parses "silhouette", "border", "crease" (the feature kinds); returns false for anything else.
bool parse_line_kind(const std::string& s, LineKind& out);

struct Piece {
    LineKind kind = LineKind::Silhouette;
    int qi = 0;                       // quantitative invisibility: 0 is visible
    std::uint32_t curve = 0;          // index of the feature curve it came from
    std::vector<glm::dvec2> points;   // pixels, DESIGN.md convention
    std::uint32_t object = 0;         // index into Drawing::object_names (0 when it is empty)
    std::vector<float> opacity = {};  // per point, in [0, 1]; empty: opaque (every kind but tone's)
    std::vector<float> width = {};    // per point, a factor of the line width; empty: 1 (tone lines
                                      // with a width by depth or edge length)
};

// An image drawn under the lines (the tone stage's toon base coat): 0x00RRGGBB, row by row from
// the top, at the drawing's size; empty: a white background.
struct RasterLayer {
    int width = 0, height = 0;
    std::vector<std::uint32_t> rgb;
    bool empty() const { return rgb.empty(); }
};

struct DrawingStats {
    std::size_t triangles = 0;
    std::size_t seam_edges = 0;  // orientation seam edges of non-orientable parts (model/orientation.hpp)
    std::size_t silhouette_edges = 0;
    std::size_t border_edges = 0;
    std::size_t crease_edges = 0;
    std::size_t curves = 0;
    std::size_t cusps = 0;
    std::size_t crossings = 0;  // image-space crossings of curves with silhouette/border edges
    std::size_t pieces = 0;
    std::size_t ray_tests = 0;
    std::string visibility = "rays";  // method: "rays" (reference) or "appel" (propagation)
    std::size_t clusters = 0;         // appel: connected sets of curves sharing a base QI
    std::size_t walks = 0;            // appel: surface walks (section 4.4)
    // appel: clusters decided by the bounding-box rule, by upper bounds from decided clusters,
    // proved totally occluded (lower bound, parity, constraints, walks), and left to the
    // reference because their offsets contradict (non-generic views, self-intersections)
    std::size_t clusters_bbox = 0, clusters_bounded = 0, clusters_occluded = 0, clusters_inconsistent = 0;
    std::string finder = "exhaustive";  // silhouette finder: "exhaustive" or "randomized"
    double fraction = 1.0;            // randomized: share of edges drawn
    double recall = -1.0;             // silhouette length found / exhaustive's (< 0: not measured)
    double seconds_load = 0.0;        // model loading and topology (0 when reused)
    double seconds_features = 0.0;
    double seconds_visibility = 0.0;
    // Its stages: the curves cut into pieces at their crossings (occluders clipped and binned,
    // the crossing search); appel's propagation (offsets, clusters, local occlusion at curve
    // ends, constraints, bounds); the walks; the ray tests. They sum to seconds_visibility,
    // but for its few clock reads.
    double seconds_pieces = 0.0, seconds_propagation = 0.0, seconds_walks = 0.0, seconds_ray_tests = 0.0;
    // Surface lines (suggestive contours, smooth contours, ridges, valleys), when asked for: their
    // curves, the vertices whose curvature could not be estimated (they draw none), the
    // crossings and ray tests of their visibility (included in the totals above), the per-view
    // curvature and extraction time, and their visibility's time (included in seconds_visibility).
    std::size_t surface_curves = 0, curvature_invalid_vertices = 0, crossings_surface = 0, surface_ray_tests = 0;
    double seconds_surface_lines = 0.0, seconds_surface_visibility = 0.0;
    // Tone lines (src/tone/), when asked for: the pass's stages (shading, blur, ridge search,
    // tracing); not part of seconds_total's features and visibility.
    double seconds_tone_shade = 0.0, seconds_tone_blur = 0.0, seconds_tone_ridges = 0.0, seconds_tone_trace = 0.0;
    // Intersection lines, when asked for: their curves (once per model, not counted in the view's
    // time), and the crossings and ray tests of their visibility (included in the totals above).
    std::size_t intersection_curves = 0, crossings_intersection = 0, intersection_ray_tests = 0;
    double seconds_output = 0.0;
    double seconds_total = 0.0;
};

struct Drawing {
    Camera camera;
    DrawingStats stats;
    std::vector<Piece> pieces;  // visible and hidden pieces; writers filter by QI
    // A scene's objects (Piece::object), in the model's order; empty for a single mesh. Writers
    // tell objects apart only when there are several.
    std::vector<std::string> object_names;
    RasterLayer base;           // under the lines (PNG/PDF painted, SVG an embedded image)
};

}  // namespace inkline
