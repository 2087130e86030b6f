// The silhouette search alone (no chaining, no visibility) of the finders along a smooth orbit
// of armadillo Loop-subdivided twice (832 k triangles), storage reused as an interactive viewer
// runs it: exhaustive as a plain scan, with the face blocks (FaceBlocks), and with the face
// blocks and the gather-free edge layout (BlockEdges, the default; also on two threads), and the
// randomized finder with coherence from an exhaustive first view. Counters: search ms per frame
// (mean, with the first views' set-up of blocks and layout, and median), share of face planes
// read. Usage: taskset -c 1 bench_finder [--benchmark_filter=...] (taskset -c 0,1 for the two
// threads); meshes come from INKLINE_DATA_DIR. Arguments: degrees per frame x 100 (0: a static
// camera).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "features/features.hpp"
#include "bench_models.hpp"
#include "pipeline.hpp"

namespace {

const inkline::Model* model(const std::string& name) { return bench_model(name); }

// The bench's orbit (src/app/bench.cpp): 20 degrees above the equator at the framing distance.
inkline::Camera orbit(const inkline::MeshTopology& t, double degrees) {
    return inkline::Camera::perspective(orbit_eye(t, degrees), t.bounds.center(), {0, 1, 0}, 30.0, 1024, 1024);
}

void run(benchmark::State& state, const char* name, inkline::FinderOptions o) {
    const auto* m = model(name);
    if (!m) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    const inkline::MeshTopology& t = m->topology();
    const double dpf = double(state.range(0)) / 100.0;
    inkline::SilhouetteFinder finder(t, o);
    inkline::Features f;
    inkline::FeatureOptions fo;
    std::vector<double> times;  // search per frame (the median is robust to the shared machine's load)
    std::vector<double> kept_times, rebuilt_times;  // coherence: frames that kept the band, frames that rebuilt it
    double search = 0.0, read = 0.0, edges = 0.0, frame = 0.0, band = 0.0, turned = 0.0, rebuilds = 0.0, sil = 0.0;
    for (auto _ : state) {
        finder.find(orbit(t, frame * dpf), fo, f);
        frame += 1.0;
        search += f.stats.seconds_search;
        times.push_back(f.stats.seconds_search);
        if (frame > 1.0) (f.stats.band_rebuilt ? rebuilt_times : kept_times).push_back(f.stats.seconds_search);
        read += double(f.stats.planes_read);
        edges += double(f.stats.edges_read);
        band += double(f.stats.band_faces);
        turned += double(f.stats.faces_turned);
        rebuilds += f.stats.band_rebuilt ? 1.0 : 0.0;
        sil += double(f.silhouette_edges.size());
    }
    const double n = double(std::max<std::int64_t>(1, state.iterations()));
    state.counters["search_ms"] = 1e3 * search / n;
    if (!times.empty()) {
        std::nth_element(times.begin(), times.begin() + std::ptrdiff_t(times.size() / 2), times.end());
        state.counters["search_median_ms"] = 1e3 * times[times.size() / 2];
    }
    state.counters["planes_read"] = read / n / double(t.face_count());
    state.counters["edges_read"] = edges / n / double(t.edge_count());
    state.counters["silhouette_edges"] = sil / n;
    if (o.kind == inkline::FinderKind::Randomized) {
        // The mean as the medians of the two kinds of frames weigh it: robust to the load of a
        // shared machine (frames that rebuild the band are a fifth of them or fewer, so the
        // overall median says nothing of their cost).
        auto median = [](std::vector<double>& v) {
            if (v.empty()) return 0.0;
            std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
            return v[v.size() / 2];
        };
        const double k = median(kept_times), r = median(rebuilt_times);
        const double share = double(rebuilt_times.size()) / double(std::max<std::size_t>(1, rebuilt_times.size() + kept_times.size()));
        state.counters["kept_median_ms"] = 1e3 * k;
        state.counters["rebuilt_median_ms"] = 1e3 * r;
        state.counters["robust_mean_ms"] = 1e3 * ((1.0 - share) * k + share * r);
        state.counters["band_faces"] = band / n;
        state.counters["faces_turned"] = turned / n;
        state.counters["rebuilds"] = rebuilds / n;
    }
}

// layout: 0 plain scan, 1 face blocks, 2 face blocks and the gather-free edge layout (the default).
void BM_Exhaustive(benchmark::State& state, const char* name, int layout, int threads) {
    inkline::FinderOptions o;
    o.blocks = layout >= 1;
    o.edge_windows = layout >= 2;
    o.threads = threads;
    run(state, name, o);
}

void BM_Coherence(benchmark::State& state, const char* name, bool blocks) {
    inkline::FinderOptions o;
    o.kind = inkline::FinderKind::Randomized;
    o.fraction = 0.0005;
    o.coherence = true;
    o.first_full = true;
    o.blocks = blocks;
    run(state, name, o);
}

}  // namespace

int main(int argc, char** argv) {
    for (const char* n : {"armadillo@2"}) {
        const char* layouts[] = {"/noblocks", "/blocks", "/windows"};
        for (int layout : {0, 1, 2})
            for (int threads : {1, 2}) {
                if (threads == 2 && layout != 2) continue;
                const std::string t = threads == 2 ? "/2threads" : "";
                benchmark::RegisterBenchmark(("exhaustive" + std::string(layouts[layout]) + t + "/" + n).c_str(),
                                             BM_Exhaustive, n, layout, threads)
                    ->Arg(0)->Arg(100)->Unit(benchmark::kMillisecond);
            }
        for (bool blocks : {false, true}) {
            const std::string b = blocks ? "/blocks" : "/noblocks";
            benchmark::RegisterBenchmark(("coherence" + b + "/" + n).c_str(), BM_Coherence, n, blocks)
                ->Arg(25)->Arg(100)->Unit(benchmark::kMillisecond);
        }
    }
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
