// The installed facade (include/inkline/inkline.hpp) over the pipeline, the style and the writers.
#include "inkline/inkline.hpp"

#include <optional>
#include <stdexcept>
#include <utility>

#include "core/error.hpp"
#include "output/styled.hpp"
#include "output/writers.hpp"
#include "pipeline.hpp"
#include "style/style.hpp"
#include "style/styled_view.hpp"

namespace inkline::api {

struct Model::Impl {
    inkline::Model model;
};

struct Drawing::Impl {
    View view;
    std::optional<StyledDrawing> styled;
    bool hidden = false;
};

namespace {

// Runs `f`, giving the caller this header's one error type whatever a stage threw for bad input.
template <class F>
auto guarded(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const inkline::Error& e) {
        throw Error(e.what());
    } catch (const std::invalid_argument& e) {
        throw Error(e.what());
    }
}

glm::dvec3 to_glm(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 from_glm(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

inkline::Camera to_internal(const Camera& c) {
    if (c.width < 1 || c.height < 1 || c.width > 32768 || c.height > 32768)
        throw Error("camera: image size " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                    " outside 1 to 32768 pixels each");
    try {
        inkline::Camera cam =
            c.ortho_height > 0.0
                ? inkline::Camera::orthographic(to_glm(c.eye), to_glm(c.target), to_glm(c.up), c.ortho_height,
                                                c.width, c.height)
                : inkline::Camera::perspective(to_glm(c.eye), to_glm(c.target), to_glm(c.up), c.fov_degrees,
                                               c.width, c.height);
        if (c.near > 0.0) cam.set_near(c.near);
        return cam;
    } catch (const std::invalid_argument& e) {
        throw Error(std::string("camera: ") + e.what());
    }
}

// The kinds named in options.lines switched on, every other kind off.
void set_kinds(const std::vector<std::string>& names, ViewOptions& opt) {
    for (auto& k : opt.features.kinds) k = false;
    SurfaceLineOptions& s = opt.surface;
    s.suggestive = s.smooth_contour = s.ridge = s.valley = false;
    bool* const surface_switch[kPieceKindCount] = {nullptr, nullptr, nullptr, nullptr,
                                                   &s.suggestive, &s.smooth_contour, &s.ridge, &s.valley};
    for (const std::string& name : names) {
        int found = -1;
        for (int i = 0; i < kPieceKindCount; ++i)
            if (LineKind(i) != LineKind::Freeform && name == to_string(LineKind(i))) found = i;
        if (found < 0)
            throw Error("lines: unknown line kind '" + name +
                        "' (expected silhouette, crease, border, suggestive, smooth-contour, ridge, valley)");
        if (found < kLineKindCount) opt.features.kinds[found] = true;
        else *surface_switch[found] = true;
    }
}

}  // namespace

std::string version() { return INKLINE_VERSION; }

Model::Model(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Model::Model(Model&&) noexcept = default;
Model& Model::operator=(Model&&) noexcept = default;
Model::~Model() = default;

Model Model::load(const std::string& path, const LoadOptions& options) {
    if (options.subdivide < 0 || options.subdivide > 6)
        throw Error("subdivide: " + std::to_string(options.subdivide) + " levels, expected 0 to 6");
    if (!(options.crease_degrees >= 0.0 && options.crease_degrees <= 180.0))
        throw Error("crease: expected an angle in [0, 180] degrees");
    return guarded([&] {
        inkline::LoadOptions lo;
        lo.strict = options.strict;
        return Model(std::make_unique<Impl>(
            Impl{inkline::Model::load(path, lo, options.crease_degrees, options.subdivide)}));
    });
}

std::size_t Model::triangles() const { return std::as_const(impl_->model).topology().face_count(); }
Vec3 Model::bounds_min() const { return from_glm(std::as_const(impl_->model).topology().bounds.lo); }
Vec3 Model::bounds_max() const { return from_glm(std::as_const(impl_->model).topology().bounds.hi); }

Camera Camera::framing(const Model& model, int width, int height) {
    Camera c;
    c.width = width;
    c.height = height;
    const inkline::Camera framed =
        inkline::Camera::framing(std::as_const(model.impl_->model).topology().bounds, width < 1 ? 1 : width, height < 1 ? 1 : height);
    c.eye = from_glm(framed.eye());
    c.target = from_glm(framed.target());
    c.up = from_glm(framed.up());
    c.fov_degrees = framed.fov_deg();
    return c;
}

Drawing::Drawing(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Drawing::Drawing(Drawing&&) noexcept = default;
Drawing& Drawing::operator=(Drawing&&) noexcept = default;
Drawing::~Drawing() = default;

int Drawing::width() const { return impl_->view.drawing.camera.width(); }
int Drawing::height() const { return impl_->view.drawing.camera.height(); }

std::vector<Polyline> Drawing::polylines() const {
    std::vector<Polyline> out;
    for (const Piece& p : impl_->view.drawing.pieces) {
        if (p.qi > 0 && !impl_->hidden) continue;
        Polyline line{to_string(p.kind), p.qi, {}};
        line.points.reserve(p.points.size());
        for (const glm::dvec2& q : p.points) line.points.push_back({q.x, q.y});
        out.push_back(std::move(line));
    }
    return out;
}

void Drawing::write(const std::string& path) const {
    guarded([&] {
        const Format format = output_format(path, "");
        if (impl_->styled && format != Format::Json) {
            write_styled(*impl_->styled, path, format);
        } else {
            OutputOptions oo;
            oo.hidden = impl_->hidden;
            write_drawing(impl_->view.drawing, path, format, oo);
        }
    });
}

Drawing draw(const Model& model, const Camera& camera, const DrawOptions& options) {
    ViewOptions opt;
    set_kinds(options.lines, opt);
    const inkline::Camera cam = to_internal(camera);
    return guarded([&] {
        std::optional<Style> style;
        if (!options.style.empty())
            style = options.styles_dir.empty() ? load_style(options.style) : load_style(options.style, options.styles_dir);
        opt.exact_hidden = options.hidden || (style && style->draw_hidden);
        const inkline::Model& m = model.impl_->model;
        auto impl = std::make_unique<Drawing::Impl>();
        impl->view = render_view(m, cam, opt);
        impl->hidden = options.hidden;
        if (style) impl->styled = stylize_view(m, cam, impl->view, *style, options.hidden);
        return Drawing(std::move(impl));
    });
}

}  // namespace inkline::api
