// A harness for profiling build_pieces alone (perf, valgrind --tool=callgrind): the default view
// of one mesh, its features found once, then build_pieces run per frame into one PieceGraph (storage
// kept, with the model's self-intersection cuts, as a ViewSession runs it). Prints the size of the
// view and the mean and least CPU time of build_pieces per frame (this thread's CPU clock).
// Usage: pieces_profile [mesh (default armadillo)] [frames (default 50)]
#include <algorithm>
#include <cstdio>
#include <string>

#include "profile_view.hpp"
#include "visibility/visibility.hpp"

int main(int argc, char** argv) {
    const std::string name = argc > 1 ? argv[1] : "armadillo";
    const int frames = argc > 2 ? std::max(1, std::stoi(argv[2])) : 50;
    const auto v = profile_view(name, "pieces_profile");
    if (!v) return 1;
    const auto& cuts = v->model->self_intersections().cuts;
    inkline::PieceGraph g;
    const FrameTimes t = time_frames(
        frames, [] {}, [&] { inkline::build_pieces(g, v->model->topology(), v->features, v->camera, &cuts, 1); });
    std::printf("%s: pieces %zu links %zu link_crossings %zu occluders %zu crossings %zu\n", name.c_str(),
                g.curves.pieces.size(), g.links.size(), g.link_crossings.size(), g.occluders.size(),
                g.curves.crossings);
    std::printf("build_pieces %.3f ms CPU per frame (%d frames) min %.3f\n", t.mean_ms, frames, t.least_ms);
    return 0;
}
