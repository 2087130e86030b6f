// A harness for profiling assign_qi_appel alone (perf, valgrind --tool=callgrind): the default
// view of one mesh, its pieces built once per frame (untimed), then assign_qi_appel timed per
// frame, as bench_frame's visibility_appel runs it (visible lines: exact_hidden off, walks on).
// Prints the size of the view (pieces, spans, ends and their vertices, crossings, pierced faces)
// and the mean and the least CPU time of assign_qi_appel per frame (this thread's CPU clock:
// less sensitive to other processes on a shared machine than wall time; the least, less still).
// Usage: appel_profile [mesh (default armadillo)] [frames (default 50)]
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "profile_view.hpp"
#include "visibility/appel.hpp"

int main(int argc, char** argv) {
    const std::string name = argc > 1 ? argv[1] : "armadillo";
    const int frames = argc > 2 ? std::max(1, std::stoi(argv[2])) : 50;
    const auto v = profile_view(name, "appel_profile");
    if (!v) return 1;
    const inkline::Model* m = v->model;
    const auto& pierced = m->self_intersecting_faces();
    inkline::PieceGraph g;
    inkline::AppelStats st;
    const FrameTimes t = time_frames(
        frames, [&] { inkline::build_pieces(g, m->topology(), v->features, v->camera, nullptr, 1); },
        [&] {
            st = inkline::assign_qi_appel(
                m->topology(), v->camera, v->features.face_front,
                [&]() -> const inkline::RayCaster& { return m->rays(); }, g, {false, m->pierced_faces(), true, 1});
        });
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
    std::printf("clusters %zu (bounded above %zu) walks %zu ray_tests %zu; assign_qi_appel %.3f ms CPU per frame "
                "(%d frames) min %.3f\n",
                st.clusters, st.clusters_bounded, st.walks, st.ray_tests, t.mean_ms, frames, t.least_ms);
    return 0;
}
