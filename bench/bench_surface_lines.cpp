// Per-view curvature lines (src/curvature/): compute_view_curvature and extract_surface_lines
// (suggestive contours, the default kinds) on one thread, along the bench's orbit (one degree a
// frame), with the model's curvature computed beforehand (once per model, not timed here).
// Reported: the medians per view of each stage and of both, in the thread's CPU time (on a shared
// machine, wall time mostly measures the other processes), and the curves and points drawn.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <ctime>
#include <vector>

#include "core/clock.hpp"
#include "bench_models.hpp"
#include "curvature/curvature.hpp"

namespace {

inkline::Camera orbit(const inkline::MeshTopology& t, double degrees) {
    return inkline::Camera::perspective(orbit_eye(t, degrees), t.bounds.center(), {0, 1, 0}, 30.0, 1024, 1024);
}

double median(std::vector<double>& v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

void per_view(benchmark::State& state, const char* name) {
    const inkline::Model* m = bench_model(name);
    if (!m) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    const inkline::MeshTopology& t = m->topology();
    const inkline::CurvatureField& field = m->curvature();
    const inkline::SurfaceLineOptions options;
    inkline::ViewCurvature view;
    inkline::SurfaceCurves curves;
    // Warm up: storage is reused from view to view, so steady state allocates nothing.
    inkline::compute_view_curvature(field, t, orbit(t, 0.0), view);
    inkline::extract_surface_lines(t, field, view, orbit(t, 0.0), options, curves);
    std::vector<double> quantities, lines, both;
    double frame = 0.0, n_curves = 0.0, n_points = 0.0;
    for (auto _ : state) {
        const inkline::Camera cam = orbit(t, frame);
        frame += 1.0;
        const double t0 = inkline::thread_cpu_seconds();
        inkline::compute_view_curvature(field, t, cam, view);
        const double t1 = inkline::thread_cpu_seconds();
        inkline::extract_surface_lines(t, field, view, cam, options, curves);
        const double t2 = inkline::thread_cpu_seconds();
        quantities.push_back(t1 - t0);
        lines.push_back(t2 - t1);
        both.push_back(t2 - t0);
        n_curves += double(curves.curves.size());
        n_points += double(curves.points.size());
        benchmark::DoNotOptimize(curves.points.data());
    }
    const double n = double(std::max<std::int64_t>(1, state.iterations()));
    state.counters["view_curvature_median_ms"] = 1e3 * median(quantities);
    state.counters["extract_median_ms"] = 1e3 * median(lines);
    state.counters["per_view_median_ms"] = 1e3 * median(both);
    state.counters["curves"] = n_curves / n;
    state.counters["points"] = n_points / n;
    state.counters["vertices"] = double(t.vertex_count());
    state.counters["faces"] = double(t.face_count());
}

}  // namespace

BENCHMARK_CAPTURE(per_view, armadillo, "armadillo")->Unit(benchmark::kMillisecond)->Iterations(360);
BENCHMARK_CAPTURE(per_view, bunny00, "bunny00")->Unit(benchmark::kMillisecond)->Iterations(360);
BENCHMARK_CAPTURE(per_view, elephant, "elephant")->Unit(benchmark::kMillisecond)->Iterations(360);

BENCHMARK_MAIN();
