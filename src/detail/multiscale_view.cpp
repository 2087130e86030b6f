// Per view: each vertex's level, the blended shape and its blended view quantities, and the
// unchanged pipeline on the blended geometry (multiscale.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/clock.hpp"
#include "detail/multiscale.hpp"
#include "detail/octahedral.hpp"

namespace inkline {

namespace {

// log2 of each vertex's own target T (its object's, else options.target_px); empty when all are
// options.target_px.
std::vector<double> vertex_log_targets(const MeshTopology& mesh, const MultiscaleViewOptions& options) {
    if (options.object_target_px.empty() || mesh.face_object.size() != mesh.face_count()) return {};
    std::vector<double> per_object(mesh.object_names.size(), std::log2(options.target_px));
    for (const auto& [name, px] : options.object_target_px)
        for (std::size_t o = 0; o < mesh.object_names.size(); ++o)
            if (mesh.object_names[o] == name && px > 0.0) per_object[o] = std::log2(px);
    std::vector<double> out(mesh.vertex_count(), std::log2(options.target_px));
    std::vector<std::uint8_t> seen(mesh.vertex_count(), 0);
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const std::uint32_t o = mesh.face_object[f];
        if (o >= per_object.size()) continue;
        for (std::uint32_t v : mesh.faces[f])
            if (!seen[v]) seen[v] = 1, out[v] = per_object[o];
    }
    return out;
}

}  // namespace

std::string unknown_detail_objects(const MeshTopology& mesh, const MultiscaleViewOptions& options) {
    std::string unknown;
    for (const auto& entry : options.object_target_px)
        if (std::find(mesh.object_names.begin(), mesh.object_names.end(), entry.first) == mesh.object_names.end())
            unknown += (unknown.empty() ? "'" : ", '") + entry.first + "'";
    return unknown;
}

void multiscale_vertex_levels(const Model& model, const MultiscaleLevels& levels, const Camera& camera,
                              const MultiscaleViewOptions& options, std::vector<float>& out) {
    const MeshTopology& mesh = model.topology();
    out.resize(mesh.vertex_count());
    const double top = double(levels.levels - 1);
    const double projected_px = levels.feature_size * camera.focal();  // L's length in pixels at distance 1
    if (levels.levels <= 1 || !(projected_px > 0.0) || !(options.target_px > 0.0)) {
        std::fill(out.begin(), out.end(), 0.0f);
        return;
    }
    const std::vector<double> log_targets = vertex_log_targets(mesh, options);
    const double log_projected = std::log2(projected_px);
    if (camera.is_ortho()) {  // the same projection everywhere: one level (per object)
        const double l = std::log2(options.target_px / projected_px);
        for (std::size_t v = 0; v < out.size(); ++v)
            out[v] = float(std::clamp(log_targets.empty() ? l : log_targets[v] - log_projected, 0.0, top));
        return;
    }
    // l = log2(d / d0) with d0 = F L / T; with a depth-dependent target T (d / d_ref)^e it gains
    // e log2(d / d_ref).
    const glm::dvec3 eye = camera.eye();
    const double log_d0 = std::log2(projected_px / options.target_px);
    const double e = options.depth_exponent;
    const double log_ref = std::log2(std::max(glm::length(eye - mesh.bounds.center()), 1e-300));
    for (std::size_t v = 0; v < out.size(); ++v) {
        const double log_d = std::log2(std::max(glm::length(eye - mesh.positions[v]), 1e-300));
        double l = log_d - (log_targets.empty() ? log_d0 : log_projected - log_targets[v]);
        if (e != 0.0) l += e * (log_d - log_ref);
        out[v] = float(std::clamp(l, 0.0, top));
    }
}

MultiscaleSession::MultiscaleSession(const Model& model, const MultiscaleLevels& levels, const ViewOptions& options,
                                     const MultiscaleViewOptions& view_options)
    : model_(&model), levels_(&levels), view_options_(view_options),
      blended_(std::make_unique<Model>(MeshTopology(model.topology()))) {
    ViewOptions o = options;
    // The finder's per-model tables of face planes go stale when the vertices move.
    o.finder.blocks = false;
    o.finder.edge_windows = false;
    session_ = std::make_unique<ViewSession>(*blended_, o);
    if (o.wants_surface_lines()) {
        surface_field_ = &model.curvature();
        session_->use_surface_fields(surface_field_, &view_);
    }
    if (levels.levels <= 1)  // the blend is M0
        known_pierced_ = std::make_unique<SelfIntersections>(model.self_intersections());
    else if (!levels.levels_self_intersect)
        known_pierced_ = std::make_unique<SelfIntersections>(
            SelfIntersections{std::vector<std::uint8_t>(model.topology().face_count(), 0), 0, {}, {}});
}

MultiscaleSession::~MultiscaleSession() = default;

namespace {

// n.v, kr, D_w kr of level k at vertex i (k = 0: the model's own curvature) for v toward the eye.
// False where that level's curvature could not be estimated.
bool level_quantities(const CurvatureField& field0, const MultiscaleLevels& levels, int k, std::size_t i,
                      const glm::vec3& v, float& nv, float& kr, float& dw) {
    if (k == 0) {
        view_curvature_at(field0.normal[i], field0.dir1[i], field0.k1[i], field0.k2[i], field0.dcurv[i], v, nv, kr, dw);
        return true;
    }
    const std::size_t a = levels.at(k, i);
    const glm::vec3 n = octahedral_decode(levels.normal_oct[a]);
    view_curvature_at(n, direction_in_frame(n, levels.dir1_angle[a]), levels.k1[a], levels.k2[a], levels.dcurv[a], v,
                      nv, kr, dw);
    return levels.valid[a] != 0;
}

}  // namespace

void MultiscaleSession::blend(const Camera& camera) {
    const MultiscaleLevels& L = *levels_;
    const MeshTopology& m0 = model_->topology();
    multiscale_vertex_levels(*model_, L, camera, view_options_, level_);
    const std::size_t n = m0.vertex_count();
    positions_.resize(n);
    const int top = L.levels - 1;
    auto split = [&](std::size_t i, int& k, float& t) {
        k = std::min(int(level_[i]), top);
        t = k == top ? 0.0f : level_[i] - float(k);
    };
    auto at_level = [&](int k, std::size_t i) { return k == 0 ? m0.positions[i] : glm::dvec3(L.position[L.at(k, i)]); };
    for (std::size_t i = 0; i < n; ++i) {
        int k;
        float t;
        split(i, k, t);
        const glm::dvec3 a = at_level(k, i);
        positions_[i] = t == 0.0f ? a : a + double(t) * (at_level(k + 1, i) - a);
    }
    blended_->move_vertices(positions_, known_pierced_.get());

    const CurvatureField* field0 = surface_field_;
    if (!field0) return;  // no surface lines asked for
    // As compute_view_curvature, per level, blended: n.v, kr and D_w kr (the seed's scalars).
    const MeshTopology& b = blended_->topology();
    view_.ndotv.resize(n);
    view_.kr.resize(n);
    view_.dwkr.resize(n);
    const bool ortho = camera.is_ortho();
    const glm::dvec3 eye = camera.eye();
    const glm::vec3 to_eye_ortho = glm::vec3(-camera.forward());
    const float nan = std::nanf("");
    for (std::size_t i = 0; i < n; ++i) {
        glm::vec3 v = to_eye_ortho;
        if (!ortho) {
            v = glm::vec3(eye - b.positions[i]);
            const float len2 = glm::dot(v, v);
            v *= len2 > 0.0f ? 1.0f / std::sqrt(len2) : 0.0f;
        }
        int k;
        float t;
        split(i, k, t);
        float nv, kr, dw;
        bool ok = level_quantities(*field0, L, k, i, v, nv, kr, dw);
        if (t != 0.0f) {
            float nv1, kr1, dw1;
            ok = level_quantities(*field0, L, k + 1, i, v, nv1, kr1, dw1) && ok;
            nv += t * (nv1 - nv);
            kr += t * (kr1 - kr);
            dw += t * (dw1 - dw);
        }
        view_.ndotv[i] = ok ? nv : nan;
        view_.kr[i] = ok ? kr : nan;
        view_.dwkr[i] = ok ? dw : nan;
    }
}

View& MultiscaleSession::render(Camera camera) {
    const auto t0 = std::chrono::steady_clock::now();
    blend(camera);
    seconds_blend_ = seconds_since(t0);
    if (session_->finder().options().kind == FinderKind::Randomized) session_->finder().reset();
    View& v = session_->render(camera);
    v.drawing.stats.seconds_features += seconds_blend_;
    v.drawing.stats.seconds_total += seconds_blend_;
    v.drawing.stats.seconds_load = model_->load_seconds();
    return v;
}

}  // namespace inkline
