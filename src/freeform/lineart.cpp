#include "freeform/lineart.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/clock.hpp"
#include "core/error.hpp"

namespace inkline::freeform {
namespace {

// Parameters between a and b (t in [0, 1]) along the shorter way around periodic directions.
glm::dvec2 lerp_uv(const Surface& s, glm::dvec2 a, glm::dvec2 b, double t) {
    auto one = [](double x, double y, const glm::dvec2& r, bool periodic) {
        double d = y - x;
        if (periodic) {
            const double w = r[1] - r[0];
            if (d > 0.5 * w) d -= w;
            if (d < -0.5 * w) d += w;
        }
        return d;
    };
    glm::dvec2 p(a.x + t * one(a.x, b.x, s.u_range, s.periodic_u), a.y + t * one(a.y, b.y, s.v_range, s.periodic_v));
    auto wrap = [](double& x, const glm::dvec2& r, bool periodic) {
        if (!periodic) return;
        const double w = r[1] - r[0];
        x = r[0] + std::fmod(std::fmod(x - r[0], w) + w, w);
    };
    wrap(p.x, s.u_range, s.periodic_u);
    wrap(p.y, s.v_range, s.periodic_v);
    return p;
}

}  // namespace

LineArt::LineArt(SurfaceList surfaces, const LineArtOptions& options, const std::string& where)
    : surfaces_(std::move(surfaces)), options_(options) {
    if (options.cones < 1 || options.cones > 100000) throw Error(where, "number of cones must be 1..100000");
    auto t0 = std::chrono::steady_clock::now();
    tess_ = tessellate(surfaces_, options.tessellation, where);
    stats_.seconds_tessellate = seconds_since(t0);
    // Occluders: the tessellation without transparent surfaces.
    TriangleMesh opaque;
    opaque.positions = tess_.mesh.positions;
    occluder_face_.assign(tess_.mesh.triangles.size(), kNoFace);
    for (std::size_t s = 0; s < surfaces_.size(); ++s) {
        if (surfaces_[s]->transparent) continue;
        const auto& g = tess_.grids[s];
        for (std::size_t c = 0; c < std::size_t(g.nu) * g.nv; ++c)
            for (std::uint32_t f : tess_.cell_faces[g.first_cell + c])
                if (f != UINT32_MAX) {
                    occluder_face_[f] = std::uint32_t(opaque.triangles.size());
                    opaque.triangles.push_back(tess_.mesh.triangles[f]);
                }
    }
    if (!opaque.triangles.empty()) {
        occluders_ = build_topology(opaque);
        rays_ = std::make_unique<RayCaster>(occluders_);
    }
    grow(options);
}

void LineArt::grow(const LineArtOptions& options) {
    if (options.cones < 1 || options.cones > 100000) throw Error("--cones", "number of cones must be 1..100000");
    options_ = options;
    Bounds3 box{glm::dvec3(1e300), glm::dvec3(-1e300)};
    for (const auto& p : tess_.mesh.positions) box.lo = glm::min(box.lo, p), box.hi = glm::max(box.hi, p);
    const double diag = glm::length(box.hi - box.lo);

    auto t0 = std::chrono::steady_clock::now();
    const auto samples = cover(surfaces_, options.points, options.seed);
    stats_.seconds_cover = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    StrokeOptions so = options.strokes;
    so.length = options.stroke_length * diag;
    strokes_ = grow_strokes(surfaces_, samples, so);
    stats_.seconds_grow = seconds_since(t0);

    t0 = std::chrono::steady_clock::now();
    center_ = box.center();
    radius_ = 0.0;
    normals_.clear();
    seeds_.clear();
    for (const auto& s : strokes_) {
        normals_.push_back(s.normal);
        seeds_.push_back(s.seed);
        radius_ = std::max(radius_, glm::length(s.seed - center_));
    }
    auto axes = cone_axes(options.cones);
    const double alpha = covering_angle(axes);
    buckets_ = std::make_unique<ConeBuckets>(std::move(axes), alpha, normals_, seeds_, options.buckets);
    stats_.seconds_buckets = seconds_since(t0);
    stats_.strokes = strokes_.size();
    stats_.cones = std::size_t(options.cones);
    stats_.bucket_entries = buckets_->entries();
    stats_.alpha_degrees = alpha * 180.0 / M_PI;
}

LineArt::~LineArt() = default;

ViewQuery LineArt::query(const Camera& camera) const {
    return make_query(camera.eye(), camera.forward(), camera.is_ortho(), center_, radius_, options_.closed);
}

int LineArt::layers_at(const Camera& camera, std::uint32_t surface, glm::dvec2 uv) const {
    if (!rays_) return 0;
    std::uint32_t f0 = UINT32_MAX, f1 = UINT32_MAX;
    glm::dvec3 p = tess_.locate(surfaces_, surface, uv, f0, f1);
    const std::uint32_t o0 = f0 == UINT32_MAX ? kNoFace : occluder_face_[f0];
    const std::uint32_t o1 = f1 == UINT32_MAX ? kNoFace : occluder_face_[f1];
    const glm::dvec3 from = camera.ray_origin(p);
    // The paper moves strokes a little towards the viewer against z-fighting; here a relative
    // 1e-7 of the distance keeps the segment off the faces around the point.
    p += 1e-7 * (from - p);
    return rays_->count_layers(from, p, o0, o1);
}

std::vector<Piece> LineArt::draw(const Camera& camera, const DrawOptions& o, DrawStats* stats) {
    DrawStats ds;
    auto t0 = std::chrono::steady_clock::now();
    const std::vector<Selected> sel = buckets_->select(query(camera), o.shader, o.cull, &ds.select);
    ds.selected = sel.size();
    ds.seconds_select = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    std::vector<Piece> out;
    const double near = camera.near_distance() > 0 ? camera.near_distance() : 0.0;
    struct Sample {
        glm::dvec2 uv;
        int qi;
    };
    for (const Selected& s : sel) {
        const Stroke& st = strokes_[s.stroke];
        const Surface& S = *surfaces_[st.surface];
        const double psi = std::min(1.0, s.psi);
        const double as = st.arc[st.seed_at], L = st.length();
        const double a0 = as - psi * as, a1 = as + psi * (L - as);
        if (!(a1 > a0)) continue;
        // The portion [a0, a1] as parameter points: interpolated ends, stroke vertices between.
        std::vector<glm::dvec2> uvs;
        auto at = [&](double a) {
            std::size_t k = std::size_t(std::upper_bound(st.arc.begin(), st.arc.end(), a) - st.arc.begin());
            k = std::clamp<std::size_t>(k, 1, st.arc.size() - 1);
            const double seg = st.arc[k] - st.arc[k - 1];
            const double t = seg > 0 ? std::clamp((a - st.arc[k - 1]) / seg, 0.0, 1.0) : 0.0;
            return lerp_uv(S, st.uv[k - 1], st.uv[k], t);
        };
        uvs.push_back(at(a0));
        for (std::size_t k = 0; k < st.arc.size(); ++k)
            if (st.arc[k] > a0 && st.arc[k] < a1) uvs.push_back(st.uv[k]);
        uvs.push_back(at(a1));
        auto qi_of = [&](glm::dvec2 uv) {
            const glm::dvec3 p = S.eval(uv.x, uv.y).p;
            if (!camera.is_ortho() && camera.depth(p) <= near) return -1;
            if (!o.visibility) return 0;
            ++ds.ray_tests;
            return layers_at(camera, st.surface, uv);
        };
        // Samples at most ~3 px apart on screen, then each change of QI located by bisection.
        std::vector<Sample> samples;
        samples.push_back({uvs[0], qi_of(uvs[0])});
        for (std::size_t k = 1; k < uvs.size(); ++k) {
            const glm::dvec2 a = uvs[k - 1], b = uvs[k];
            const double px = glm::length(camera.project(S.eval(b.x, b.y).p) - camera.project(S.eval(a.x, a.y).p));
            const int n = std::clamp(int(std::ceil(px / 3.0)), 1, 32);
            for (int q = 1; q <= n; ++q) {
                const glm::dvec2 uv = lerp_uv(S, a, b, double(q) / n);
                const Sample next{uv, qi_of(uv)};
                const glm::dvec2 prev_uv = samples.back().uv;
                if (next.qi != samples.back().qi) {
                    double lo = 0.0, hi = 1.0;  // qi(lo) = previous, qi(hi) = next
                    const int qlo = samples.back().qi;
                    for (int it = 0; it < 10; ++it) {
                        const double mid = 0.5 * (lo + hi);
                        (qi_of(lerp_uv(S, prev_uv, uv, mid)) == qlo ? lo : hi) = mid;
                    }
                    samples.push_back({lerp_uv(S, prev_uv, uv, lo), qlo});
                    samples.push_back({lerp_uv(S, prev_uv, uv, hi), next.qi});
                }
                samples.push_back(next);
            }
        }
        // Pieces of constant QI.
        Piece cur;
        cur.kind = LineKind::Freeform;
        cur.curve = s.stroke;
        cur.qi = samples[0].qi;
        auto flush = [&]() {
            if (cur.qi >= 0 && cur.points.size() >= 2) out.push_back(cur);
            cur.points.clear();
        };
        for (std::size_t k = 0; k < samples.size(); ++k) {
            if (samples[k].qi != cur.qi) {
                flush();
                cur.qi = samples[k].qi;
            }
            if (cur.qi >= 0) cur.points.push_back(camera.project(S.eval(samples[k].uv.x, samples[k].uv.y).p));
        }
        flush();
    }
    ds.pieces = out.size();
    ds.seconds_visibility = seconds_since(t0);
    if (stats) *stats = ds;
    return out;
}

}  // namespace inkline::freeform
