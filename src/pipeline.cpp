#include "pipeline.hpp"

#include <chrono>

namespace inkline {
namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

Model Model::load(const std::string& path, double crease_degrees) {
    const auto t0 = std::chrono::steady_clock::now();
    Model m(load_mesh(path), crease_degrees);
    m.load_seconds_ = seconds_since(t0);
    return m;
}

Model::Model(const TriangleMesh& mesh, double crease_degrees) : topo_(build_topology(mesh, crease_degrees)) {}

const RayCaster& Model::rays() const {
    if (!rays_) rays_ = std::make_unique<RayCaster>(topo_);
    return *rays_;
}

View render_view(const Model& model, Camera camera, const ViewOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    if (camera.near_distance() <= 0.0) camera.set_near(default_near(model.topology()));
    View v;
    v.features = extract_features(model.topology(), camera, options.features);
    const auto t_index = std::chrono::steady_clock::now();
    const RayCaster& rays = model.rays();  // built once per model, timed apart from the view
    const auto t1 = std::chrono::steady_clock::now();
    VisibleCurves curves = compute_visibility(model.topology(), v.features, camera, rays);

    Drawing& d = v.drawing;
    d.camera = camera;
    d.pieces = std::move(curves.pieces);
    v.spans = std::move(curves.spans);
    DrawingStats& s = d.stats;
    s.triangles = model.topology().face_count();
    s.silhouette_edges = v.features.silhouette_edges.size();
    s.border_edges = v.features.border_edges.size();
    s.crease_edges = v.features.crease_edges.size();
    s.curves = v.features.curves.size();
    s.cusps = v.features.cusp_vertices.size();
    s.crossings = curves.crossings;
    s.pieces = d.pieces.size();
    s.ray_tests = curves.ray_tests;
    s.seconds_load = model.load_seconds();
    s.seconds_features = std::chrono::duration<double>(t_index - t0).count();
    s.seconds_visibility = seconds_since(t1);
    s.seconds_total = s.seconds_features + s.seconds_visibility;
    return v;
}

}  // namespace inkline
