#include "app/freeform_cli.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include <glm/geometric.hpp>

#include "core/error.hpp"
#include "freeform/lineart.hpp"

namespace inkline {

namespace {

glm::dvec3 vec3(const std::string& flag, const std::string& s) {
    std::vector<std::string> parts;
    std::stringstream ss(s);
    for (std::string p; std::getline(ss, p, ',');) parts.push_back(p);
    if (parts.size() != 3) throw Error(flag, "expected x,y,z, got '" + s + "'");
    const glm::dvec3 v(parse_number(flag, parts[0]), parse_number(flag, parts[1]), parse_number(flag, parts[2]));
    if (!(glm::length(v) > 0)) throw Error(flag, "expected a non-zero direction");
    return glm::normalize(v);
}

double integer(const std::string& flag, const std::string& s, double lo, double hi) {
    const double v = parse_number(flag, s);
    if (v < lo || v > hi || v != std::floor(v))
        throw Error(flag, "expected an integer from " + std::to_string((long long)lo) + " to " + std::to_string((long long)hi));
    return v;
}

double in_range(const std::string& flag, const std::string& s, double lo, double hi) {
    const double v = parse_number(flag, s);
    if (!(v >= lo && v <= hi)) throw Error(flag, "expected a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
}
}  // namespace

std::vector<Flag> freeform_flags(FreeformArgs& a) {
    const auto value = [&a](const char* name, const char* form, const char* help) {
        return Flag{name, form, help, [&a, name](const std::string& v) { a.flags[name] = v; }};
    };
    return {
        value("--strokes", "KIND",
              "Elber's line art: iso, iso-u, iso-v, curvature, curvature-max, curvature-min, isophote, direction"),
        value("--direction", "X,Y,Z", "the strokes' direction for --strokes=direction"),
        value("--points", "N", "strokes grown, from points covering the surfaces evenly (default 4000)"),
        value("--cones", "M", "cones over the Gauss map that bucket the strokes (default 50)"),
        value("--buckets", "redundant|exclusive", "a stroke in every cone near its normal (default), or in the nearest only"),
        value("--shader", "diffuse|silhouette|combined", "which strokes a view draws (default combined)"),
        value("--decay-dif", "C", "diffuse shader's exponent, in [0.01, 1000] (default 2)"),
        value("--tau-dif", "T", "diffuse shader's threshold, in [0, 1] (default 0.1)"),
        value("--decay-sil", "D", "silhouette shader's exponent, in [0.01, 1000] (default 2)"),
        value("--tau-sil", "T", "silhouette shader's threshold, in [0, 1] (default 0.2)"),
        value("--stroke-length", "F", "longest stroke, a share of the bounding box's diagonal (default 0.06)"),
        value("--tessellation", "N", "segments along a Bezier patch's side, 2 to 512"),
        value("--cover-seed", "S", "random seed of the points' coverage (default 1)"),
        switch_flag("--transparent", a.transparent, true, "every stroke drawn as visible (all surfaces transparent)"),
        switch_flag("--open", a.open, true, "the surfaces bound no solid: back-facing strokes are drawn too"),
        switch_flag("--no-cull", a.no_cull, true, "visit every cone, not only the contributing ones (the same strokes)"),
    };
}

bool is_freeform_model(const std::string& path) { return freeform::is_freeform_path(path); }

struct FreeformRender::Impl {
    FreeformArgs args;
    std::string path;
    std::unique_ptr<freeform::LineArt> art;
    freeform::LineArtOptions options;
    freeform::DrawOptions draw;
    bool light_given = false;
};

FreeformRender::FreeformRender(const std::string& path, const FreeformArgs& args) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.args = args;
    m.path = path;
    const auto& f = args.flags;
    auto has = [&](const char* k) { return f.count(k) > 0; };
    if (has("--strokes") && !freeform::parse_stroke_field(f.at("--strokes"), m.options.strokes.field))
        throw Error("--strokes", "unknown stroke kind '" + f.at("--strokes") +
                                     "' (expected iso, iso-u, iso-v, curvature, curvature-max, curvature-min, isophote, direction)");
    if (has("--direction")) m.options.strokes.direction = vec3("--direction", f.at("--direction"));
    if (has("--points")) m.options.points = std::size_t(integer("--points", f.at("--points"), 1, 1e8));
    if (has("--cones")) m.options.cones = int(integer("--cones", f.at("--cones"), 1, 100000));
    if (has("--buckets")) {
        const std::string& b = f.at("--buckets");
        if (b == "redundant") m.options.buckets = freeform::BucketMode::Redundant;
        else if (b == "exclusive") m.options.buckets = freeform::BucketMode::Exclusive;
        else throw Error("--buckets", "unknown mode '" + b + "' (expected redundant or exclusive)");
    }
    if (has("--shader") && !freeform::parse_shader(f.at("--shader"), m.draw.shader.kind))
        throw Error("--shader", "unknown shader '" + f.at("--shader") + "' (expected diffuse, silhouette, combined)");
    if (!args.lights.empty()) m.draw.shader.lights = args.lights, m.light_given = true;  // --light (app/flags.hpp)
    if (has("--decay-dif")) m.draw.shader.c = in_range("--decay-dif", f.at("--decay-dif"), 0.01, 1000);
    if (has("--tau-dif")) m.draw.shader.tau_dif = in_range("--tau-dif", f.at("--tau-dif"), 0, 1);
    if (has("--decay-sil")) m.draw.shader.d = in_range("--decay-sil", f.at("--decay-sil"), 0.01, 1000);
    if (has("--tau-sil")) m.draw.shader.tau_sil = in_range("--tau-sil", f.at("--tau-sil"), 0, 1);
    if (has("--stroke-length")) m.options.stroke_length = in_range("--stroke-length", f.at("--stroke-length"), 1e-6, 10);
    if (has("--tessellation")) {
        const int n = int(integer("--tessellation", f.at("--tessellation"), 2, 512));
        m.options.tessellation.bezier_segments = n;
        m.options.tessellation.primitive_segments = std::max(8, 8 * n);
    }
    if (has("--cover-seed")) m.options.seed = std::uint64_t(integer("--cover-seed", f.at("--cover-seed"), 0, 9007199254740992.0));
    m.options.closed = !args.open;
    m.draw.cull = !args.no_cull;
    m.draw.visibility = !args.transparent;
    freeform::LineArtOptions first = m.options;
    first.points = 0;  // strokes are grown once the camera is known (isophote direction)
    m.art = std::make_unique<freeform::LineArt>(freeform::load_surfaces(path), first, path);
}

FreeformRender::~FreeformRender() = default;

const TriangleMesh& FreeformRender::mesh() const { return impl_->art->tessellation().mesh; }

void FreeformRender::add_strokes(const Camera& camera, Drawing& drawing, bool quiet) {
    Impl& m = *impl_;
    if (!m.args.flags.count("--strokes")) {
        if (m.args.flags.size() > 0 || m.args.transparent || m.args.no_cull)
            throw Error("--strokes", "line-art flags given without --strokes");
        return;
    }
    const glm::dvec3 v = glm::normalize(camera.eye() - camera.target());
    m.options.strokes.isophote_direction = v;  // "silhouette lines" of this view direction
    if (!m.light_given)  // a headlight from the upper left
        m.draw.shader.lights = {glm::normalize(v + 1.0 * camera.upward() - 0.7 * camera.right())};
    m.art->grow(m.options);
    freeform::DrawStats ds;
    std::vector<Piece> pieces = m.art->draw(camera, m.draw, &ds);
    drawing.stats.pieces += pieces.size();
    drawing.stats.ray_tests += ds.ray_tests;
    for (auto& p : pieces) drawing.pieces.push_back(std::move(p));
    if (!quiet) {
        const auto& s = m.art->stats();
        std::printf("freeform: %zu strokes, %zu cones (covering angle %.4f deg, %zu bucket entries, redundancy %.3f); "
                    "pre-process %.3f s (tessellation %.3f, coverage %.3f, growth %.3f, buckets %.3f)\n",
                    s.strokes, s.cones, s.alpha_degrees, s.bucket_entries,
                    s.strokes ? double(s.bucket_entries) / s.strokes : 0.0,
                    s.seconds_tessellate + s.seconds_cover + s.seconds_grow + s.seconds_buckets, s.seconds_tessellate,
                    s.seconds_cover, s.seconds_grow, s.seconds_buckets);
        std::printf("freeform view: %zu cones visited, %zu culled back-facing, %zu culled by the shader; %zu strokes "
                    "tested, %zu drawn, %zu pieces, %zu ray tests; select %.5f s, visibility %.4f s\n",
                    ds.select.cones_visited, ds.select.cones_culled_back, ds.select.cones_culled_shader,
                    ds.select.strokes_tested, ds.selected, ds.pieces, ds.ray_tests, ds.seconds_select,
                    ds.seconds_visibility);
    }
}

}  // namespace inkline
