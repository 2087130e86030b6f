// The tone pass (src/tone/) stage by stage: shading, blur, ridge search, tracing, on the framed
// camera of a sample mesh, at given sizes and thread counts; medians and minima of wall time over
// repeated passes into the same ToneResult (the window's steady state: storage reused).
// Usage: bench_tone [MESH ...]   (default armadillo); prints a markdown table.
#include <algorithm>
#include <cmath>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <string>
#include <vector>

#include "pipeline.hpp"
#include "tone/tone.hpp"

using namespace inkline;

namespace {
double thread_cpu_seconds() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> meshes;
    for (int i = 1; i < argc; ++i) meshes.push_back(argv[i]);
    if (meshes.empty()) meshes = {"armadillo"};
    constexpr int kRuns = 15;
    std::printf("| mesh | size | threads | shade | blur | ridges | trace | total (median) | total (min) | CPU (1 thread) | dark, highlight lines |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const std::string& name : meshes) {
        const Model model = Model::load(std::string(INKLINE_DATA_DIR) + "/meshes/" + name + ".off");
        const tone::ToneMesh normals = tone::prepare_tone_mesh(model.topology());
        for (auto [w, h] : {std::pair{800, 600}, std::pair{1024, 1024}})
            for (int threads : {1, 2}) {
                Camera cam = Camera::framing(model.topology().bounds, w, h);
                cam.set_near(default_near(model.topology()));
                tone::ToneOptions o;
                o.threads = threads;
                tone::ToneResult r;
                tone::render_tone(model.topology(), normals, cam, o, true, true, r);  // warm-up
                std::vector<double> shade, blur, ridges, trace, total, cpu;
                for (int k = 0; k < kRuns; ++k) {
                    const double c0 = thread_cpu_seconds();
                    tone::render_tone(model.topology(), normals, cam, o, true, true, r);
                    cpu.push_back(thread_cpu_seconds() - c0);
                    shade.push_back(r.seconds.shade);
                    blur.push_back(r.seconds.blur);
                    ridges.push_back(r.seconds.ridges);
                    trace.push_back(r.seconds.trace);
                    total.push_back(r.seconds.total());
                }
                std::size_t dark = 0;
                for (const Piece& p : r.pieces) dark += p.kind == LineKind::ToneDark;
                std::printf("| %s | %dx%d | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %s | %zu, %zu |\n", name.c_str(), w, h,
                            threads, 1e3 * median(shade), 1e3 * median(blur), 1e3 * median(ridges), 1e3 * median(trace),
                            1e3 * median(total), 1e3 * *std::min_element(total.begin(), total.end()),
                            threads == 1 ? std::to_string(int(std::lround(1e3 * median(cpu)))).c_str() : "-", dark,
                            r.pieces.size() - dark);
                std::fflush(stdout);
            }
    }
    return 0;
}
