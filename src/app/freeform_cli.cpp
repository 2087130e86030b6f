#include "app/freeform_cli.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>

#include "core/error.hpp"
#include "freeform/lineart.hpp"

namespace inkline {

namespace {

glm::dvec3 direction(const std::string& flag, const std::string& s) {
    const glm::dvec3 v = parse_vec3(flag, s);
    if (!(glm::length(v) > 0)) throw Error(flag, "expected a non-zero direction");
    return glm::normalize(v);
}

std::uint64_t whole(const std::string& flag, const std::string& s, double lo, double hi, const char* range) {
    const double v = parse_number(flag, s);
    if (v < lo || v > hi || v != std::floor(v)) throw Error(flag, std::string("expected an integer from ") + range);
    return std::uint64_t(v);
}

double in_range(const std::string& flag, const std::string& s, double lo, double hi, const char* range) {
    const double v = parse_number(flag, s);
    if (!(v >= lo && v <= hi)) throw Error(flag, std::string("expected a number in ") + range);
    return v;
}
}  // namespace

std::vector<Flag> freeform_flags(FreeformArgs& a) {
    // Each setter parses its value into the options at once and counts the flag as given.
    const auto value = [&a](const char* name, const char* form, const char* help, auto parse) {
        return Flag{name, form, help, [&a, name, parse](const std::string& v) {
                        parse(name, v);
                        ++a.given;
                    }};
    };
    auto& o = a.options;
    auto& d = a.draw;
    return {
        value("--strokes", "KIND",
              "Elber's line art: iso, iso-u, iso-v, curvature, curvature-max, curvature-min, isophote, direction",
              [&a, &o](const char* f, const std::string& v) {
                  if (!freeform::parse_stroke_field(v, o.strokes.field))
                      throw Error(f, "unknown stroke kind '" + v +
                                         "' (expected iso, iso-u, iso-v, curvature, curvature-max, curvature-min, "
                                         "isophote, direction)");
                  a.strokes = true;
              }),
        value("--direction", "X,Y,Z", "the strokes' direction for --strokes=direction",
              [&o](const char* f, const std::string& v) { o.strokes.direction = direction(f, v); }),
        value("--points", "N", "strokes grown, from points covering the surfaces evenly (default 4000)",
              [&o](const char* f, const std::string& v) { o.points = whole(f, v, 1, 1e8, "1 to 10^8"); }),
        value("--cones", "M", "cones over the Gauss map that bucket the strokes (default 50)",
              [&o](const char* f, const std::string& v) { o.cones = int(whole(f, v, 1, 100000, "1 to 100000")); }),
        value("--buckets", "redundant|exclusive", "a stroke in every cone near its normal (default), or in the nearest only",
              [&o](const char* f, const std::string& v) {
                  if (v == "redundant") o.buckets = freeform::BucketMode::Redundant;
                  else if (v == "exclusive") o.buckets = freeform::BucketMode::Exclusive;
                  else throw Error(f, "unknown mode '" + v + "' (expected redundant or exclusive)");
              }),
        value("--shader", "diffuse|silhouette|combined", "which strokes a view draws (default combined)",
              [&d](const char* f, const std::string& v) {
                  if (!freeform::parse_shader(v, d.shader.kind))
                      throw Error(f, "unknown shader '" + v + "' (expected diffuse, silhouette, combined)");
              }),
        value("--decay-dif", "C", "diffuse shader's exponent, in [0.01, 1000] (default 2)",
              [&d](const char* f, const std::string& v) { d.shader.c = in_range(f, v, 0.01, 1000, "[0.01, 1000]"); }),
        value("--tau-dif", "T", "diffuse shader's threshold, in [0, 1] (default 0.1)",
              [&d](const char* f, const std::string& v) { d.shader.tau_dif = in_range(f, v, 0, 1, "[0, 1]"); }),
        value("--decay-sil", "D", "silhouette shader's exponent, in [0.01, 1000] (default 2)",
              [&d](const char* f, const std::string& v) { d.shader.d = in_range(f, v, 0.01, 1000, "[0.01, 1000]"); }),
        value("--tau-sil", "T", "silhouette shader's threshold, in [0, 1] (default 0.2)",
              [&d](const char* f, const std::string& v) { d.shader.tau_sil = in_range(f, v, 0, 1, "[0, 1]"); }),
        value("--stroke-length", "F", "longest stroke, a share of the bounding box's diagonal (default 0.06)",
              [&o](const char* f, const std::string& v) { o.stroke_length = in_range(f, v, 1e-6, 10, "[1e-6, 10]"); }),
        value("--tessellation", "N", "segments along a Bezier patch's side, 2 to 512",
              [&o](const char* f, const std::string& v) {
                  const int n = int(whole(f, v, 2, 512, "2 to 512"));
                  o.tessellation.bezier_segments = n;
                  o.tessellation.primitive_segments = std::max(8, 8 * n);
              }),
        value("--cover-seed", "S", "random seed of the points' coverage (default 1)",
              [&o](const char* f, const std::string& v) { o.seed = whole(f, v, 0, 9007199254740992.0, "0 to 2^53"); }),
        switch_flag("--transparent", a.transparent, true, "every stroke drawn as visible (all surfaces transparent)"),
        switch_flag("--open", a.open, true, "the surfaces bound no solid: back-facing strokes are drawn too"),
        switch_flag("--no-cull", a.no_cull, true, "visit every cone, not only the contributing ones (the same strokes)"),
    };
}

bool is_freeform_model(const std::string& path) { return freeform::is_freeform_path(path); }

struct FreeformRender::Impl {
    FreeformArgs args;
    std::unique_ptr<freeform::LineArt> art;
};

FreeformRender::FreeformRender(const std::string& path, const FreeformArgs& args) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    if (!args.strokes && (args.given > 0 || args.transparent || args.no_cull)) throw BadValue("--strokes: line-art flags given without --strokes");
    m.args = args;
    if (!args.lights.empty()) m.args.draw.shader.lights = args.lights;  // --light (app/flags.hpp)
    m.args.options.closed = !args.open;
    m.args.draw.cull = !args.no_cull;
    m.args.draw.visibility = !args.transparent;
    freeform::LineArtOptions first = m.args.options;
    first.points = 0;  // strokes are grown once the camera is known (isophote direction)
    m.art = std::make_unique<freeform::LineArt>(freeform::load_surfaces(path), first, path);
}

FreeformRender::~FreeformRender() = default;

const TriangleMesh& FreeformRender::mesh() const { return impl_->art->tessellation().mesh; }

void FreeformRender::add_strokes(const Camera& camera, Drawing& drawing, bool quiet) {
    Impl& m = *impl_;
    if (!m.args.strokes) return;
    const glm::dvec3 v = glm::normalize(camera.eye() - camera.target());
    m.args.options.strokes.isophote_direction = v;  // "silhouette lines" of this view direction
    if (m.args.lights.empty())  // a headlight from the upper left
        m.args.draw.shader.lights = {glm::normalize(v + 1.0 * camera.upward() - 0.7 * camera.right())};
    m.art->grow(m.args.options);
    freeform::DrawStats ds;
    std::vector<Piece> pieces = m.art->draw(camera, m.args.draw, &ds);
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
