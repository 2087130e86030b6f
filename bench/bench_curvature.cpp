// estimate_curvature (per-vertex curvature and its derivative, once per model) on the sample meshes,
// as Model::curvature() computes it on first use: the meshes as Model::load orders them (Hilbert
// order). Counters: median and minimum over the iterations of wall ms and of the thread's CPU ms (on
// the shared machine, wall time grows with the other work that preempts us; CPU time much less),
// vertices, triangles, bytes of the field per vertex. Usage:
//   taskset -c 1 build/bench/bench_curvature --benchmark_repetitions=1 [--benchmark_filter=armadillo]
// (one core; meshes from INKLINE_DATA_DIR; dragon is ChineseDragon-10kv).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <vector>

#include "core/clock.hpp"
#include "bench_models.hpp"
#include "curvature/curvature.hpp"
#include "pipeline.hpp"

namespace {

double thread_cpu_ms() { return 1e3 * inkline::thread_cpu_seconds(); }

double median(std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

double field_bytes(const inkline::CurvatureField& f) {
    return double(f.normal.capacity() * sizeof(glm::vec3) + f.dir1.capacity() * sizeof(glm::vec3) +
                  (f.k1.capacity() + f.k2.capacity() + f.point_area.capacity()) * sizeof(float) +
                  f.dcurv.capacity() * sizeof(std::array<float, 4>) + f.valid.capacity());
}

void run(benchmark::State& state, const char* name) {
    const inkline::Model* m = bench_model(name);
    if (!m) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    const inkline::MeshTopology& t = m->topology();
    std::vector<double> ms, cpu;
    double bytes = 0.0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        const double c0 = thread_cpu_ms();
        inkline::CurvatureField f = inkline::estimate_curvature(t);
        cpu.push_back(thread_cpu_ms() - c0);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        benchmark::DoNotOptimize(f.k1.data());
        bytes = field_bytes(f);
    }
    state.counters["median_ms"] = median(ms);
    state.counters["min_ms"] = *std::min_element(ms.begin(), ms.end());
    state.counters["median_cpu_ms"] = median(cpu);
    state.counters["min_cpu_ms"] = *std::min_element(cpu.begin(), cpu.end());
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
