// inkline as a library: load a model, set a camera, compute a drawing, write it.
//
//   #include <inkline/inkline.hpp>
//   inkline::api::Model model = inkline::api::Model::load("bunny.off");
//   inkline::api::Camera camera = inkline::api::Camera::framing(model, 800, 600);
//   inkline::api::Drawing drawing = inkline::api::draw(model, camera);
//   drawing.write("bunny.svg");   // .svg .pdf .png .json, by the extension
//
// A small facade over the stages of src/ (which are not installed and may change): only standard
// types cross it, so a program built against one version keeps compiling against the next.
// Conventions (camera, pixels, QI, JSON) are those of `inkline render`: pixel coordinates are
// continuous, origin top-left, y down; QI 0 is visible, QI k lies behind k layers of surface.
// Every function reports what a user can get wrong (a file, a value) by throwing
// inkline::api::Error, a one-line message naming the file or option and the problem.
#pragma once

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "inkline/version.hpp"

namespace inkline::api {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// "0.1.0": the library's version (INKLINE_VERSION in inkline/version.hpp is the headers').
std::string version();

struct Vec3 {
    double x = 0.0, y = 0.0, z = 0.0;
};

struct Camera;
struct DrawOptions;
class Drawing;

struct LoadOptions {
    double crease_degrees = 40.0;  // an edge whose face normals differ by more is a crease
    int subdivide = 0;             // Loop subdivision levels, 0 to 6
    bool strict = false;           // refuse what tolerant loading repairs (degenerate faces, ...)
};

// A mesh (OBJ, OFF, PLY, STL) or a scene (glTF, FBX, Collada, ... as Assimp reads them), loaded
// once and drawn from any number of cameras; movable, not copyable.
class Model {
public:
    static Model load(const std::string& path, const LoadOptions& options = {});
    Model(Model&&) noexcept;
    Model& operator=(Model&&) noexcept;
    ~Model();

    std::size_t triangles() const;
    Vec3 bounds_min() const;
    Vec3 bounds_max() const;

    struct Impl;

private:
    friend struct Camera;
    friend Drawing draw(const Model&, const Camera&, const DrawOptions&);
    explicit Model(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// A perspective camera (or orthographic when ortho_height > 0), image width x height pixels.
struct Camera {
    Vec3 eye{0.0, 0.0, 5.0}, target{0.0, 0.0, 0.0}, up{0.0, 1.0, 0.0};
    double fov_degrees = 30.0;   // full vertical field of view, in (0, 180)
    double ortho_height = 0.0;   // > 0: orthographic, this many world units high
    double near = 0.0;           // near plane distance; 0: a small share of the model's size
    int width = 1024, height = 1024;

    // The whole model in view, as `inkline render` frames it with no camera flag: looking at the
    // bounding box's centre from the direction (1, 0.6, 1.4), fov 30, +Y up.
    static Camera framing(const Model& model, int width = 1024, int height = 1024);
};

struct DrawOptions {
    // Line kinds, named as in the JSON: silhouette, crease, border, suggestive, smooth-contour,
    // ridge, valley.
    std::vector<std::string> lines{"silhouette", "crease", "border"};
    bool hidden = false;  // also compute and draw hidden lines (QI > 0)
    // A style preset (clean, technical, sketchy, charcoal, ink-brush, hatched, illustration) or a
    // style file (a path ending in .json); empty: the plain look. A styled drawing writes SVG, PDF
    // or PNG (JSON keeps the exact pieces, unstyled).
    std::string style;
    // Where preset names are found; empty: $INKLINE_STYLES, else the styles installed beside the
    // running program. A program built against the installed package can pass the package's
    // inkline_STYLES_DIR (set by find_package(inkline)).
    std::string styles_dir;
};

// One piece of line with a single QI, in pixels.
struct Polyline {
    std::string kind;  // "silhouette", "crease", ...
    int qi = 0;
    std::vector<std::array<double, 2>> points;
};

class Drawing {
public:
    Drawing(Drawing&&) noexcept;
    Drawing& operator=(Drawing&&) noexcept;
    ~Drawing();

    int width() const;
    int height() const;
    // Every piece computed (hidden ones only with DrawOptions::hidden), unstyled.
    std::vector<Polyline> polylines() const;
    // Writes SVG, PDF, PNG or JSON, chosen by the extension; written to a temporary file and
    // renamed, so a failure leaves no file.
    void write(const std::string& path) const;

    struct Impl;

private:
    friend Drawing draw(const Model&, const Camera&, const DrawOptions&);
    explicit Drawing(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// Silhouettes and the other asked-for lines of `model` seen from `camera`, hidden lines removed
// exactly (quantitative invisibility), stylized when options.style says so.
Drawing draw(const Model& model, const Camera& camera, const DrawOptions& options = {});

}  // namespace inkline::api
