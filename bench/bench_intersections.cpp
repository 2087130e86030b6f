// Intersection lines per model: the self-intersection search (once per model, every render pays
// it for the cuts), the curves built from its pairs (once per model, only when intersection lines
// are drawn), and one framed view's intersection visibility, propagated and by the ray reference.
// Usage: bench_intersections [--no-views] [MODEL...] (default: every sample mesh of
// INKLINE_DATA_DIR/meshes; --no-views: the search and the curves only);
// models are loaded tolerantly (scenes through Assimp). One Markdown row per model.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/clock.hpp"
#include "core/error.hpp"
#include "pipeline.hpp"

namespace {

// Seconds the intersection lines add to one view (the curves already built): the fastest of five
// renders with them less the fastest of five without (the machine is noisy).
double view_seconds(const inkline::Model& model, const inkline::Camera& cam, inkline::VisibilityMethod method,
                    std::size_t& pieces, std::size_t& ray_tests) {
    inkline::ViewOptions o;
    o.visibility = method;
    o.features.intersection = true;
    inkline::ViewSession session(model, o);
    session.render(cam);  // (warm: the ray-test index and the first view's storage)
    auto fastest = [&] {
        double best = 1e300;
        for (int k = 0; k < 5; ++k) {
            const auto t0 = std::chrono::steady_clock::now();
            session.render(cam);
            best = std::min(best, inkline::seconds_since(t0));
        }
        return best;
    };
    const double with_s = fastest();
    const inkline::View& with = session.render(cam);
    pieces = 0;
    for (const auto& p : with.drawing.pieces) pieces += p.kind == inkline::LineKind::Intersection;
    ray_tests = with.drawing.stats.intersection_ray_tests;
    session.set_intersection_lines(false);
    return with_s - fastest();
}

void run(const std::string& path, bool views) {
    const auto t0 = std::chrono::steady_clock::now();
    const inkline::Model model = inkline::Model::load(path, inkline::LoadOptions{});
    const double load_s = inkline::seconds_since(t0);
    const auto t1 = std::chrono::steady_clock::now();
    const inkline::SelfIntersections& si = model.self_intersections();
    const double search_s = inkline::seconds_since(t1);
    const auto t2 = std::chrono::steady_clock::now();
    const inkline::IntersectionCurves& c = model.intersection_curves();
    const double curves_s = inkline::seconds_since(t2);
    std::size_t closed = 0, meets = 0;
    for (const auto& curve : c.curves) closed += curve.closed, meets += curve.meets_other;
    const inkline::Camera cam = inkline::Camera::framing(model.topology().bounds, 1024, 1024);
    std::size_t pieces = 0, ray_tests = 0, ref_pieces = 0, ref_ray_tests = 0;
    double appel_s = 0.0, rays_s = 0.0;
    if (views) {
        appel_s = view_seconds(model, cam, inkline::VisibilityMethod::Appel, pieces, ray_tests);
        rays_s = view_seconds(model, cam, inkline::VisibilityMethod::Rays, ref_pieces, ref_ray_tests);
    }
    std::printf("| %s | %zu | %.3f | %zu | %.4f | %zu (%zu closed, %zu meet) | %.4f | %zu, %zu rays: %.5f | %zu rays: %.5f |\n",
                std::filesystem::path(path).filename().c_str(), model.topology().face_count(), load_s, si.pairs.size(),
                search_s, c.curves.size(), closed, meets, curves_s, pieces, ray_tests, appel_s, ref_ray_tests, rays_s);
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> paths(argv + 1, argv + argc);
    const bool views = paths.empty() || paths[0] != "--no-views";
    if (!views) paths.erase(paths.begin());
    if (paths.empty())
        for (const auto& e : std::filesystem::directory_iterator(std::string(INKLINE_DATA_DIR) + "/meshes"))
            paths.push_back(e.path().string());
    std::sort(paths.begin(), paths.end());
    std::printf("| model | triangles | load s | pairs | search s | curves | curves s | view: pieces, ray tests, extra s (appel) | rays: ray tests, extra s |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    for (const auto& p : paths) {
        try {
            run(p, views);
        } catch (const std::exception& e) {
            std::printf("| %s | refused: %s |\n", std::filesystem::path(p).filename().c_str(), e.what());
        }
    }
}
