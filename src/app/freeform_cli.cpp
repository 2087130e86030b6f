#include "app/freeform_cli.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include <glm/geometric.hpp>

#include "app/cli.hpp"
#include "core/error.hpp"
#include "freeform/lineart.hpp"

namespace inkline {

const char* kFreeformUsage =
    "SURFACES: .bpt (Bezier patches, e.g. examples/teapot.bpt) or .json (src/freeform/README.md):\n"
    "  silhouettes and borders of the tessellation, and with --strokes Elber's line art:\n"
    "  [--strokes=iso|iso-u|iso-v|curvature|curvature-max|curvature-min|isophote|direction]\n"
    "  [--direction=x,y,z (for --strokes=direction)] [--points=N]\n"
    "  [--cones=M] [--buckets=redundant|exclusive] [--shader=diffuse|silhouette|combined]\n"
    "  [--light=x,y,z] [--decay-dif=C] [--tau-dif=T] [--decay-sil=D] [--tau-sil=T]\n"
    "  [--stroke-length=F (of the diagonal)] [--tessellation=N] [--cover-seed=S]\n"
    "  [--transparent] [--open] [--no-cull]\n";

namespace {
const char* kKeys[] = {"--strokes", "--points", "--cones", "--buckets", "--shader", "--light", "--decay-dif",
                       "--tau-dif", "--decay-sil", "--tau-sil", "--stroke-length", "--tessellation", "--cover-seed", "--direction"};

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

bool take_freeform_flag(const std::string& key, const std::string& value, FreeformArgs& a) {
    for (const char* k : kKeys)
        if (key == k) return a.flags[key] = value, true;
    return false;
}

bool take_freeform_switch(const std::string& arg, FreeformArgs& a) {
    if (arg == "--transparent") return a.transparent = true;
    if (arg == "--no-cull") return a.no_cull = true;
    if (arg == "--open") return a.open = true;
    return false;
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
    if (has("--light")) m.draw.shader.lights = {vec3("--light", f.at("--light"))}, m.light_given = true;
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
