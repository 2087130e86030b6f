// A harness for profiling assign_qi_appel alone (perf, valgrind --tool=callgrind): the default
// view of one mesh, its pieces built once per frame (untimed), then assign_qi_appel timed per
// frame, as bench_frame's visibility_appel runs it (visible lines: exact_hidden off, walks on).
// Prints the size of the view (pieces, spans, ends and their vertices, crossings, pierced faces)
// and the mean and the least CPU time of assign_qi_appel per frame (this thread's CPU clock:
// less sensitive to other processes on a shared machine than wall time; the least, less still).
// Usage: appel_profile [mesh (default armadillo)] [frames (default 50)]
#include <algorithm>
#include <ctime>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_models.hpp"
#include "visibility/appel.hpp"

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
        std::fprintf(stderr, "appel_profile: mesh %s not found (run scripts/setup.sh)\n", name.c_str());
        return 1;
    }
    auto cam = inkline::Camera::framing(m->topology().bounds, 1024, 1024);
    cam.set_near(inkline::default_near(m->topology()));
    const inkline::Features f = inkline::extract_features(m->topology(), cam);
    const auto& pierced = m->self_intersecting_faces();
    inkline::PieceGraph g;
    double seconds = 0.0, best = 1e30;
    inkline::AppelStats st;
    for (int k = 0; k < frames; ++k) {
        inkline::build_pieces(g, m->topology(), f, cam, nullptr, 1);
        const double t0 = thread_seconds();
        st = inkline::assign_qi_appel(
            m->topology(), cam, f.face_front, [&]() -> const inkline::RayCaster& { return m->rays(); }, g,
            {false, m->pierced_faces(), true, 1});
        const double dt = thread_seconds() - t0;
        seconds += dt;
        best = std::min(best, dt);
    }
    std::size_t spans = 0;
    for (const auto& s : g.curves.spans) spans += s.size();
    std::vector<std::uint32_t> verts;
    for (const auto& e : g.ends) verts.push_back(e.vertex);
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    std::printf("%s: pieces %zu spans %zu links %zu link_crossings %zu ends %zu end_vertices %zu occluders %zu "
                "pierced_faces %zu\n",
                name.c_str(), g.curves.pieces.size(), spans, g.links.size(), g.link_crossings.size(), g.ends.size(),
                verts.size(), g.occluders.size(), std::size_t(std::count(pierced.begin(), pierced.end(), 1)));
    std::printf("clusters %zu walks %zu ray_tests %zu; assign_qi_appel %.3f ms CPU per frame (%d frames) min %.3f\n", st.clusters,
                st.walks, st.ray_tests, 1e3 * seconds / frames, frames, 1e3 * best);
    return 0;
}
