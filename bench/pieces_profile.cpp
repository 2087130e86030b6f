// A harness for profiling build_pieces alone (perf, valgrind --tool=callgrind): the default view
// of one mesh, its features found once, then build_pieces run per frame into one PieceGraph (storage
// kept, with the model's self-intersection cuts, as a ViewSession runs it). Prints the size of the
// view and the mean and least CPU time of build_pieces per frame (this thread's CPU clock).
// Usage: pieces_profile [mesh (default armadillo)] [frames (default 50)]
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <string>

#include "bench_models.hpp"
#include "visibility/visibility.hpp"

namespace {
double thread_seconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
}  // namespace

int main(int argc, char** argv) {
    const std::string name = argc > 1 ? argv[1] : "armadillo";
    const int frames = argc > 2 ? std::max(1, std::stoi(argv[2])) : 50;
    const inkline::Model* m = bench_model(name);
    if (!m) {
        std::fprintf(stderr, "pieces_profile: mesh %s not found (run scripts/setup.sh)\n", name.c_str());
        return 1;
    }
    auto cam = inkline::Camera::framing(m->topology().bounds, 1024, 1024);
    cam.set_near(inkline::default_near(m->topology()));
    const inkline::Features f = inkline::extract_features(m->topology(), cam);
    const auto& cuts = m->self_intersections().cuts;
    inkline::PieceGraph g;
    double seconds = 0.0, best = 1e30;
    for (int k = 0; k < frames; ++k) {
        const double t0 = thread_seconds();
        inkline::build_pieces(g, m->topology(), f, cam, &cuts, 1);
        const double dt = thread_seconds() - t0;
        seconds += dt;
        best = std::min(best, dt);
    }
    std::printf("%s: pieces %zu links %zu link_crossings %zu occluders %zu crossings %zu\n", name.c_str(),
                g.curves.pieces.size(), g.links.size(), g.link_crossings.size(), g.occluders.size(),
                g.curves.crossings);
    std::printf("build_pieces %.3f ms CPU per frame (%d frames) min %.3f\n", 1e3 * seconds / frames, frames, 1e3 * best);
    return 0;
}
