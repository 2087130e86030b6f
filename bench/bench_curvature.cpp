// estimate_curvature (per-vertex curvature and its derivative, once per model) on the sample meshes,
// as Model::curvature() computes it on first use: the meshes as Model::load orders them (Hilbert
// order). Counters: median and minimum wall ms over the iterations (the minimum: the run least
// disturbed by the shared machine's other work), vertices, triangles, bytes of the field per vertex. Usage:
//   taskset -c 1 build/bench/bench_curvature --benchmark_repetitions=1 [--benchmark_filter=armadillo]
// (one core; meshes from INKLINE_DATA_DIR; dragon is ChineseDragon-10kv).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "bench_models.hpp"
#include "curvature/curvature.hpp"
#include "pipeline.hpp"

namespace {

double field_bytes(const inkline::CurvatureField& f) {
    return double(f.normal.capacity() * sizeof(glm::vec3) + f.dir1.capacity() * sizeof(glm::vec3) +
                  (f.k1.capacity() + f.k2.capacity() + f.point_area.capacity()) * sizeof(float) +
                  f.dcurv.capacity() * sizeof(std::array<float, 4>) + f.valid.capacity());
}

void run(benchmark::State& state, const char* name) {
    const inkline::Model* m = bench_model(name);
    if (!m) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    const inkline::MeshTopology& t = m->topology();
    std::vector<double> ms;
    double bytes = 0.0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        inkline::CurvatureField f = inkline::estimate_curvature(t);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        benchmark::DoNotOptimize(f.k1.data());
        bytes = field_bytes(f);
    }
    std::nth_element(ms.begin(), ms.begin() + std::ptrdiff_t(ms.size() / 2), ms.end());
    state.counters["median_ms"] = ms[ms.size() / 2];
    state.counters["min_ms"] = *std::min_element(ms.begin(), ms.end());
    state.counters["vertices"] = double(t.vertex_count());
    state.counters["triangles"] = double(t.face_count());
    state.counters["bytes_per_vertex"] = bytes / double(std::max<std::size_t>(1, t.vertex_count()));
}

}  // namespace

BENCHMARK_CAPTURE(run, armadillo, "armadillo")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(run, bunny00, "bunny00")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(run, elephant, "elephant")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(run, dragon, "ChineseDragon-10kv")->Unit(benchmark::kMillisecond)->MinTime(2.0);

BENCHMARK_MAIN();
