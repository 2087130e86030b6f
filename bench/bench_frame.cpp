// Time per stage of one frame (features; features + visibility by ray tests or by propagation;
// visibility by propagation alone) on the sample meshes with the default camera. Usage: bench_frame [--benchmark_filter=...]; meshes come from INKLINE_DATA_DIR.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "bench_models.hpp"
#include "pipeline.hpp"

namespace {

// "name" or "name@N": N rounds of Loop subdivision (armadillo@1 ~208 k, @2 ~832 k triangles).
const char* kMeshes[] = {"fandisk", "bunny00",  "armadillo",   "elephant",
                         "ChineseDragon-10kv", "knot1", "armadillo@1", "armadillo@2"};

// The mesh, with its ray-test index and self-intersections built (once per model, outside the
// frames measured).
const inkline::Model* model(const std::string& name) {
    const inkline::Model* m = bench_model(name);
    if (m) {
        m->rays();
        m->self_intersecting_faces();
    }
    return m;
}

void BM_Features(benchmark::State& state, const char* name) {
    const auto* m = model(name);
    if (!m) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    const auto cam = inkline::Camera::framing(m->topology().bounds, 1024, 1024);
    for (auto _ : state) benchmark::DoNotOptimize(inkline::extract_features(m->topology(), cam));
    state.counters["triangles"] = double(m->topology().face_count());
}

// Features of consecutive frames from one ViewSession (storage reused, as an interactive viewer
// runs): the steady-state cost of the feature stage.
void BM_FeaturesSession(benchmark::State& state, const char* name) {
    const auto* m = model(name);
    if (!m) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    const auto cam = inkline::Camera::framing(m->topology().bounds, 1024, 1024);
    inkline::ViewSession session(*m);
    double search = 0.0, chain = 0.0;
    for (auto _ : state) {
        const auto& f = session.find(cam);
        search += f.stats.seconds_search;
        chain += f.stats.seconds_chain;
    }
    const double n = double(std::max<std::int64_t>(1, state.iterations()));
    state.counters["search_ms"] = 1e3 * search / n;
    state.counters["chain_ms"] = 1e3 * chain / n;
}

// A full frame from one ViewSession (features with storage reused, then visibility by propagation).
void BM_FrameSession(benchmark::State& state, const char* name) {
    const auto* m = model(name);
    if (!m) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    const auto cam = inkline::Camera::framing(m->topology().bounds, 1024, 1024);
    inkline::ViewOptions opt;
    opt.exact_hidden = false;
    inkline::ViewSession session(*m, opt);
    double vis = 0.0, feat = 0.0;
    for (auto _ : state) {
        const auto& v = session.render(cam);
        vis += v.drawing.stats.seconds_visibility;
        feat += v.drawing.stats.seconds_features;
    }
    const double n = double(std::max<std::int64_t>(1, state.iterations()));
    state.counters["features_ms"] = 1e3 * feat / n;
    state.counters["vis_ms"] = 1e3 * vis / n;
}

// The same frame with suggestive contours too (the model's curvature computed once, outside the
// frames measured): the per-view curvature, the lines' extraction and their visibility.
void BM_FrameSessionSuggestive(benchmark::State& state, const char* name) {
    const auto* m = model(name);
    if (!m) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    m->curvature();
    const auto cam = inkline::Camera::framing(m->topology().bounds, 1024, 1024);
    inkline::ViewOptions opt;
    opt.exact_hidden = false;
    opt.surface.suggestive = true;
    inkline::ViewSession session(*m, opt);
    double lines = 0.0, lines_vis = 0.0, vis = 0.0;
    std::size_t curves = 0;
    for (auto _ : state) {
        const auto& v = session.render(cam);
        lines += v.drawing.stats.seconds_surface_lines;
        lines_vis += v.drawing.stats.seconds_surface_visibility;
        vis += v.drawing.stats.seconds_visibility;
        curves = v.drawing.stats.surface_curves;
    }
    const double n = double(std::max<std::int64_t>(1, state.iterations()));
    state.counters["suggestive_ms"] = 1e3 * lines / n;
    state.counters["suggestive_vis_ms"] = 1e3 * lines_vis / n;
    state.counters["vis_ms"] = 1e3 * vis / n;
    state.counters["suggestive_curves"] = double(curves);
}

// A full frame (features + visibility, no drawing) with one visibility method.
void BM_Frame(benchmark::State& state, const char* name, inkline::VisibilityMethod method, bool walk) {
    const auto* m = model(name);
    if (!m) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    const auto cam = inkline::Camera::framing(m->topology().bounds, 1024, 1024);
    inkline::ViewOptions opt;
    opt.visibility = method;
    opt.exact_hidden = false;  // as `inkline render` without --hidden: visible lines
    opt.walk = walk;
    std::size_t sil = 0, rays = 0, pieces = 0, walks = 0;
    double vis_seconds = 0.0;
    for (auto _ : state) {
        auto v = inkline::render_view(*m, cam, opt);
        vis_seconds += v.drawing.stats.seconds_visibility;
        pieces = v.drawing.stats.pieces;
        walks = v.drawing.stats.walks;
        sil = v.drawing.stats.silhouette_edges;
        rays = v.drawing.stats.ray_tests;
        benchmark::DoNotOptimize(v);
    }
    state.counters["silhouette_edges"] = double(sil);
    state.counters["ray_tests"] = double(rays);
    state.counters["pieces"] = double(pieces);
    state.counters["walks"] = double(walks);
    // The visibility stage alone (wall time per frame, as measured by render_view), in ms.
    state.counters["vis_ms"] = 1e3 * vis_seconds / double(std::max<std::int64_t>(1, state.iterations()));
    state.counters["sil_edges_per_s"] = benchmark::Counter(double(sil), benchmark::Counter::kIsIterationInvariantRate);
}

// The visibility stage alone by propagation (features computed once, outside the loop), as
// render_view runs it for visible lines: build_pieces + assign_qi_appel.
void BM_Visibility(benchmark::State& state, const char* name, bool walk, int threads) {
    const auto* m = model(name);
    if (!m) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    auto cam = inkline::Camera::framing(m->topology().bounds, 1024, 1024);
    cam.set_near(inkline::default_near(m->topology()));
    const inkline::Features f = inkline::extract_features(m->topology(), cam);
    std::size_t rays = 0, walks = 0;
    inkline::PieceGraph g;  // storage kept from frame to frame, as a ViewSession does
    for (auto _ : state) {
        inkline::build_pieces(g, m->topology(), f, cam, nullptr, threads);
        const auto st = inkline::assign_qi_appel(
            m->topology(), cam, f.face_front, [&]() -> const inkline::RayCaster& { return m->rays(); }, g,
            {false, m->pierced_faces(), walk, threads});
        rays = st.ray_tests;
        walks = st.walks;
        benchmark::DoNotOptimize(g);
    }
    state.counters["ray_tests"] = double(rays);
    state.counters["walks"] = double(walks);
}

// build_pieces alone (clipping, projection, the crossing search, the pieces; no QI), storage kept
// from frame to frame as a ViewSession does.
void BM_Pieces(benchmark::State& state, const char* name) {
    const auto* m = model(name);
    if (!m) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    auto cam = inkline::Camera::framing(m->topology().bounds, 1024, 1024);
    cam.set_near(inkline::default_near(m->topology()));
    const inkline::Features f = inkline::extract_features(m->topology(), cam);
    inkline::PieceGraph g;
    for (auto _ : state) {
        inkline::build_pieces(g, m->topology(), f, cam, nullptr, 1);
        benchmark::DoNotOptimize(g);
    }
    std::size_t edges = 0;
    for (const auto& c : f.curves) edges += c.edges.size();
    state.counters["curve_edges"] = double(edges);
    state.counters["occluders"] = double(g.occluders.size());
    state.counters["crossings"] = double(g.curves.crossings);
    state.counters["pieces"] = double(g.curves.pieces.size());
}

int reg = [] {
    for (const char* n : kMeshes) {
        benchmark::RegisterBenchmark((std::string("features/") + n).c_str(), BM_Features, n)->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark((std::string("features_session/") + n).c_str(), BM_FeaturesSession, n)
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark((std::string("frame_appel_session/") + n).c_str(), BM_FrameSession, n)
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark((std::string("frame_appel_session_suggestive/") + n).c_str(),
                                     BM_FrameSessionSuggestive, n)
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark((std::string("frame_rays/") + n).c_str(), BM_Frame, n,
                                     inkline::VisibilityMethod::Rays, true)->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark((std::string("frame_appel/") + n).c_str(), BM_Frame, n,
                                     inkline::VisibilityMethod::Appel, true)->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark((std::string("frame_appel_nowalk/") + n).c_str(), BM_Frame, n,
                                     inkline::VisibilityMethod::Appel, false)->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark((std::string("visibility_appel/") + n).c_str(), BM_Visibility, n, true, 1)
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark((std::string("build_pieces/") + n).c_str(), BM_Pieces, n)
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark((std::string("visibility_appel_nowalk/") + n).c_str(), BM_Visibility, n, false, 1)
            ->Unit(benchmark::kMillisecond);
        // build_pieces and assign_qi_appel on two threads (large views; wall time: UseRealTime)
        benchmark::RegisterBenchmark((std::string("visibility_appel_2threads/") + n).c_str(), BM_Visibility, n, true, 2)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    }
    return 0;
}();

}  // namespace

BENCHMARK_MAIN();
