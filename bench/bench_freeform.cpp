// Elber's cone buckets (src/freeform/): per-view selection time with cone culling, visiting every
// cone (no culling, the per-frame mark still removing duplicates) and a brute-force scan of all
// strokes, for 10 k, 100 k and 1 M stroke normals of the Utah teapot and m = 20, 50, 130 cones;
// each iteration is one view of an orbit of 16 (scenarios below). Also the
// pre-process: bucket construction, and the whole LineArt pre-process for 10 k strokes.
// Usage: bench_freeform [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>

#include <glm/geometric.hpp>

#include "freeform/cones.hpp"
#include "freeform/lineart.hpp"
#include "freeform/strokes.hpp"
#include "freeform/tessellate.hpp"

using namespace inkline::freeform;

namespace {

const std::string kTeapot = std::string(INKLINE_EXAMPLES_DIR) + "/teapot.bpt";

struct Normals {
    std::vector<glm::dvec3> n, p;
};

const Normals& normals(std::size_t r) {
    static std::map<std::size_t, Normals> cache;
    auto& c = cache[r];
    if (c.n.empty()) {
        SurfaceList teapot = load_bpt(kTeapot);
        tessellate(teapot, {}, "teapot.bpt");
        for (const auto& s : cover(teapot, r, 1)) {
            const SurfacePoint sp = teapot[s.surface]->eval(s.uv.x, s.uv.y);
            const glm::dvec3 n = unit_normal(sp, teapot[s.surface]->sign);
            if (glm::length(n) < 0.5) continue;
            c.n.push_back(n);
            c.p.push_back(sp.p);
        }
    }
    return c;
}

struct Axes {
    std::vector<glm::dvec3> axes;
    double alpha;
};
const Axes& axes(int m) {
    static std::map<int, Axes> cache;
    auto& a = cache[m];
    if (a.axes.empty()) a.axes = cone_axes(m), a.alpha = covering_angle(a.axes);
    return a;
}

// Scenarios: 0 silhouette shader, perspective (eye 12 units away: view directions over the teapot
// spread by beta = 17 deg, which widens every cone); 1 silhouette, orthographic (the paper's
// single viewing direction); 2 combined, perspective; 3 diffuse with a high threshold, orthographic.
ViewQuery view(int k, bool ortho) {
    const double t = 2 * M_PI * k / 16.0;
    const glm::dvec3 c(0.2, 0, 1.5);
    const glm::dvec3 eye = c + 12.0 * glm::dvec3(std::cos(t), std::sin(t), 0.5);
    return make_query(eye, glm::normalize(c - eye), ortho, c, 3.5, true);
}

Shader shader(int scenario) {
    Shader s;
    s.kind = scenario == 2 ? ShaderKind::Combined : scenario == 3 ? ShaderKind::Diffuse : ShaderKind::Silhouette;
    s.lights = {glm::normalize(glm::dvec3(1, 1, 2))};
    s.c = 2.0;
    s.tau_dif = scenario == 3 ? 0.6 : 0.3;
    s.d = 4.0;
    s.tau_sil = 0.3;
    return s;
}

const char* kScenario[] = {"silhouette perspective", "silhouette ortho", "combined perspective", "diffuse ortho"};

// mode 0: cone culling; 1: every cone; 2: brute-force scan.
void BM_View(benchmark::State& state) {
    const std::size_t r = std::size_t(state.range(0));
    const int m = int(state.range(1)), mode = int(state.range(2)), scenario = int(state.range(3));
    const bool ortho = scenario == 1 || scenario == 3;
    const Normals& n = normals(r);
    const Axes& a = axes(m);
    ConeBuckets b(a.axes, a.alpha, n.n, n.p, BucketMode::Redundant);
    const Shader sh = shader(scenario);
    int k = 0;
    std::size_t drawn = 0, tested = 0;
    for (auto _ : state) {
        const ViewQuery q = view(k++ % 16, ortho);
        if (mode == 2) {
            auto s = select_all(n.n, n.p, q, sh);
            drawn += s.size();
            tested += n.n.size();
            benchmark::DoNotOptimize(s.data());
        } else {
            SelectStats st;
            auto s = b.select(q, sh, mode == 0, &st);
            drawn += s.size();
            tested += st.strokes_tested;
            benchmark::DoNotOptimize(s.data());
        }
    }
    state.counters["strokes"] = double(n.n.size());
    state.counters["drawn_per_view"] = double(drawn) / double(state.iterations());
    state.counters["tested_per_view"] = double(tested) / double(state.iterations());
    state.SetLabel(std::string(mode == 0 ? "cull " : mode == 1 ? "all-cones " : "brute-force ") + kScenario[scenario]);
}

void BM_BuildBuckets(benchmark::State& state) {
    const Normals& n = normals(std::size_t(state.range(0)));
    const Axes& a = axes(int(state.range(1)));
    for (auto _ : state) {
        ConeBuckets b(a.axes, a.alpha, n.n, n.p, BucketMode::Redundant);
        benchmark::DoNotOptimize(b.entries());
    }
}

// Computing the m axes (spiral, repulsion, pushing into the holes), then their covering angle.
void BM_ConeAxes(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(optimize_cone_axes(int(state.range(0))));
}
void BM_CoveringAngle(benchmark::State& state) {
    const auto ax = cone_axes(int(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(covering_angle(ax));
}

void BM_PreprocessTeapot(benchmark::State& state) {
    for (auto _ : state) {
        LineArtOptions o;
        o.points = std::size_t(state.range(0));
        o.strokes.field = StrokeField(state.range(1));
        LineArt art(load_bpt(kTeapot), o, "teapot.bpt");
        benchmark::DoNotOptimize(art.stats().strokes);
    }
    state.SetLabel(state.range(1) == int(StrokeField::Iso) ? "iso" : state.range(1) == int(StrokeField::Curvature) ? "curvature" : "isophote");
}

}  // namespace

BENCHMARK(BM_View)
    ->ArgsProduct({{10000, 100000, 1000000}, {20, 50, 130}, {0, 1, 2}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BuildBuckets)->ArgsProduct({{10000, 100000, 1000000}, {20, 50, 130}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ConeAxes)->Arg(20)->Arg(50)->Arg(130)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CoveringAngle)->Arg(20)->Arg(50)->Arg(130)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PreprocessTeapot)
    ->Args({10000, int(StrokeField::Iso)})
    ->Args({10000, int(StrokeField::Curvature)})
    ->Args({10000, int(StrokeField::Isophote)})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

BENCHMARK_MAIN();
