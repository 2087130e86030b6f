// Tone stage: line drawings via abstracted shading (Lee, Markosian, Lee, Hughes, SIGGRAPH 2007;
// ../shared/seeds/002_*, sections 3.1-3.4), on the CPU, plus tracing of the accepted pixels into
// vector polylines (which the paper does not do).
//
// Takes: the model's MeshTopology (smoothed corner normals prepared once: ToneMesh), a Camera
// (its size is the image size), lights as world directions, and ToneOptions.
// Gives (ToneResult): the tone image (diffuse) and the specular channel, both blurred with a
// Gaussian of size w, per-pixel line opacity for dark lines and for highlight lines (with the
// ridge point and direction behind each), the traced polylines (Pieces of kind ToneDark and
// ToneHighlight, opacity per point) and a toon-shaded base coat.
//
// Conventions: tone 1 is white (background, fully lit), 0 black. Pixel (i, j) covers
// [i, i+1] x [j, j+1] (DESIGN.md: y down), its sample is at its centre. The quadratic fit uses
// local coordinates in units of the sample spacing w/2 (so the constant matrix H does not depend
// on w), and so curvature thresholds are in tone units per (w/2)^2: the same thresholds select
// the same lines at any w.
//
// Errors: tone_options_error says what is wrong with options (one line; the CLI makes it a usage
// error). The functions themselves assume checked options.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "model/topology.hpp"

namespace inkline::tone {

// A single-channel float image, row by row from the top.
struct Image {
    int width = 0, height = 0;
    std::vector<float> pixels;
    void resize(int w, int h, float value) {
        width = w, height = h;
        pixels.assign(std::size_t(w) * std::size_t(h), value);
    }
    float at(int x, int y) const { return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
    // Bilinear at a continuous point (pixel centres at +0.5), clamped to the border.
    float sample(double x, double y) const;
};

// Per model, once: a normal per face corner, averaged over the faces around the vertex whose
// normal is within the crease angle of this face's (smooth shading that keeps creases sharp).
struct ToneMesh {
    std::vector<std::array<glm::vec3, 3>> corner_normals;
    // Per vertex: the line width's scale by local edge length (section 3.4): the mean length of
    // the vertex's edges over the mesh's mean edge length, clamped to [kMinWidthScale, 1].
    std::vector<float> vertex_width_scale;
};
ToneMesh prepare_tone_mesh(const MeshTopology& mesh);

// Section 3.4's optional line width: constant w, or w times a scale in [kMinWidthScale, 1] per
// pixel: by depth, the model's nearest possible depth (the front of its bounding sphere) over the
// pixel's depth (distant surfaces get thinner lines); by edge length, ToneMesh's vertex scale
// interpolated over the surface (finely tessellated regions get thinner lines). The fit's spacing,
// the search's reach and the fall-off scale with it; the thresholds keep their meaning at w (the
// curvature is compared per (w/2)^2); traced points carry it as their width.
enum class ToneWidthBy { Constant, Depth, EdgeLength };
constexpr double kMinWidthScale = 0.25;

struct ToneOptions {
    // World directions towards the lights (need not be unit); empty: default_light(camera).
    std::vector<glm::dvec3> lights;
    double specular_exponent = 40.0;  // Blinn-Phong exponent of the specular channel, >= 1
    double width = 6.0;               // w: line width in px; blur size, sample spacing w/2
    double beta = 0.2;                // share of the way moved toward the ridge at each step, [0, 1]
    int steps = 5;                    // ridge search steps (the paper's 5)
    // Soft thresholds c_l < c_u on the larger curvature magnitude (section 3.3), dark lines and
    // highlight lines (the paper sets a higher one for highlights).
    double dark_lower = 0.015, dark_upper = 0.05;
    double highlight_lower = 0.05, highlight_upper = 0.12;
    bool distance_falloff = true;  // opacity falls to 0 as the distance to the ridge reaches w/2
    bool counterchange = true;     // times 1 - t for dark lines, t for highlight lines
    double min_opacity = 0.05;     // pixels below this are not traced
    double min_length = -1.0;      // traced polylines shorter (px) are dropped; < 0: w
    int toon_bands = 3;            // base coat: 2 to 4 tone bands
    ToneWidthBy width_by = ToneWidthBy::Constant;
    int threads = 1;
};

// One line naming the problem ("--tone-width: ...") or empty when the options are usable.
std::string tone_options_error(const ToneOptions& options);

// The default light: a headlight from the upper left (as the freeform shaders' default).
glm::dvec3 default_light(const Camera& camera);

// ---- Stage 1: the tone image -----------------------------------------------------------

struct ShadedImages {
    Image tone;                         // mean over lights of max(0, n.L); background 1
    Image specular;                     // max over lights of max(0, n.h)^e where n.L > 0; background 0
    std::vector<std::uint8_t> covered;  // 1 where a surface is seen
    Image width_scale;                  // section 3.4's scale per pixel (1 off the surface); empty: constant w
    // Working storage of the z-buffer, kept so that a pass over the same size allocates nothing
    // (fresh pages cost as much as the rasterization).
    std::vector<float> closeness;
    std::vector<glm::vec3> normal;
};
// Z-buffer rasterization of the mesh at the camera's size (near plane clipped), two-sided
// shading with the interpolated corner normals (perspective-correct).
void shade(const MeshTopology& mesh, const ToneMesh& normals, const Camera& camera, const ToneOptions& options,
           ShadedImages& out);

// Separable Gaussian of size w: sigma = w / 4 (the kernel's +-2 sigma span w), cut at 3 sigma,
// border clamped. w <= 0 copies.
// `scratch` (optional) keeps the intermediate image between calls.
void gaussian_blur(const Image& in, double width, Image& out, int threads = 1, Image* scratch = nullptr);

// Section 3.4 by depth: the model's nearest possible depth along the camera's forward axis (the
// front of its bounding sphere; a small positive depth when the eye is inside it), and the scale
// per covered pixel from the z-buffer's closeness (1/depth, or -depth orthographic).
double nearest_model_depth(const MeshTopology& mesh, const Camera& camera);
void depth_width_scale(const MeshTopology& mesh, const Camera& camera, const std::vector<float>& closeness,
                       int threads, Image& scale);

// ---- Stage 2: ridges and valleys -------------------------------------------------------

// H = (X^T X)^-1 X^T for the 3x3 samples at (-1..1, -1..1), rows (x^2 2xy y^2 x y 1), samples
// ordered row by row from (-1, -1). Computed once.
const std::array<std::array<double, 9>, 6>& fit_matrix();
// Coefficients a0..a5 of f = a0 x^2 + 2 a1 xy + a2 y^2 + a3 x + a4 y + a5 fitted to 9 samples.
std::array<double, 6> fit_quadratic(const std::array<double, 9>& samples);

// The line of a fit (section 3.1), in sample units around the fit's origin.
struct RidgeLine {
    double curvature = 0.0;  // eigenvalue of M of larger magnitude (> 0: valley, < 0: ridge)
    double other = 0.0;      // the other eigenvalue
    glm::dvec2 normal{1, 0};  // its unit eigenvector u: across the line
    double offset = 0.0;     // the line passes through offset * normal (the singular case too)
    glm::dvec2 centre{0.0};  // c = -M^-1 (a3 a4) / 2 where M is regular, else 0
};
RidgeLine ridge_line(const std::array<double, 6>& a);

enum class Polarity { Dark, Light };  // valleys (dark lines) or ridges (highlight lines)

// Per pixel: opacity (0: no line) and, where it is > 0, the point of the ridge line nearest to
// the pixel's centre and the line's unit direction. A spot (the other curvature of the same sign
// and over half the larger: a round specular highlight) is a horizontal dash through its centre c.
struct RidgeField {
    int width = 0, height = 0;
    std::vector<float> opacity;
    std::vector<float> width_scale;  // the line width's scale per pixel (section 3.4); empty: 1
    std::vector<glm::vec2> point, direction;
};
// The search of section 3.2 and the opacity of 3.3 over a blurred channel; `tone` is the blurred
// tone image counterchange reads. lower/upper: c_l, c_u.
// `scale` (optional, section 3.4): the line width's scale per pixel.
void detect_ridges(const Image& channel, const Image& tone, Polarity polarity, double lower, double upper,
                   const ToneOptions& options, RidgeField& out, const Image* scale = nullptr);
// Dark lines (c_l, c_u: options' dark_*) and highlight lines (highlight_*) of one channel in one
// pass (a pixel's first fit starts at most one of the two searches); a null field is not wanted.
void detect_ridges_both(const Image& channel, const Image& tone, RidgeField* dark, RidgeField* light,
                        const ToneOptions& options, const Image* scale = nullptr);
// Per pixel the larger opacity of a and b (with its point and direction): highlight lines from
// the tone image and the specular channel.
void merge_max(RidgeField& a, const RidgeField& b);

// ---- Stage 3: tracing ------------------------------------------------------------------

// Pixels with opacity >= min_opacity, thinned to the local maximum across the line, chained along
// the line direction; points at the sub-pixel ridge positions, opacity per point.
std::vector<Piece> trace_lines(const RidgeField& field, LineKind kind, const ToneOptions& options);

// ---- The whole pass --------------------------------------------------------------------

struct ToneTimes {
    double shade = 0.0, blur = 0.0, ridges = 0.0, trace = 0.0;
    double total() const { return shade + blur + ridges + trace; }
};

struct ToneResult {
    ShadedImages shaded;
    Image tone_blurred, specular_blurred, blur_scratch;
    RidgeField specular;  // highlight lines of the specular channel, before merge_max
    RidgeField dark, highlight;
    std::vector<Piece> pieces;  // ToneDark then ToneHighlight polylines (as asked)
    ToneTimes seconds;
};

// Shades, blurs, detects and (trace: the default) traces the kinds asked for (dark, highlight).
void render_tone(const MeshTopology& mesh, const ToneMesh& normals, const Camera& camera, const ToneOptions& options,
                 bool dark, bool highlight, ToneResult& out, bool trace = true);

// Toon base coat: `bands` flat grey levels of `tone` where `covered` (white elsewhere), as
// 0x00RRGGBB pixels for a RasterLayer. The blurred tone gives smooth band borders on noisy meshes.
RasterLayer toon_base(const Image& tone, const std::vector<std::uint8_t>& covered, int bands);

}  // namespace inkline::tone
