// The preview window's pipeline without OpenGL: views per second along the bench's orbit, with one
// view at a time on two threads (`inkline view --in-flight=1`) or two views at once, each session on
// one thread, taking the views in turn (`--in-flight=2`, the default on two cores). The window's
// options: the randomized finder with frame coherence from an exhaustive first view, visible lines.
// Prints the views per second and the silhouette edges summed over the views (the two ways find the
// same silhouettes: each session follows its own last view exactly).
// Also the mean time a view of its features and of its visibility (each view's own clock: with two at
// once, each is about twice its share of the wall time).
// Usage: inflight_probe 1|2 [mesh (default armadillo@2)] [frames (200)] [arc degrees (180)]
//        [finder: coherent (the window's default) | exhaustive]
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "bench_models.hpp"

int main(int argc, char** argv) {
    const int lanes = argc > 1 ? std::stoi(argv[1]) : 2;
    const std::string name = argc > 2 ? argv[2] : "armadillo@2";
    const int frames = argc > 3 ? std::max(1, std::stoi(argv[3])) : 200;
    const double arc = argc > 4 ? std::stod(argv[4]) : 180.0;
    const std::string finder = argc > 5 ? argv[5] : "coherent";
    if ((lanes != 1 && lanes != 2) || (finder != "coherent" && finder != "exhaustive")) {
        std::fprintf(stderr, "inflight_probe: expected 1 or 2 views at once, and coherent or exhaustive\n");
        return 2;
    }
    const inkline::Model* m = bench_model_for(name, "inflight_probe");
    if (!m) return 1;
    const inkline::MeshTopology& t = m->topology();
    inkline::ViewOptions o;  // as `inkline view` sets them
    o.finder.kind = finder == "coherent" ? inkline::FinderKind::Randomized : inkline::FinderKind::Exhaustive;
    o.finder.coherence = true;
    o.finder.first_full = true;
    o.exact_hidden = false;
    o.threads = lanes == 1 ? 2 : 1;
    const auto camera = [&](int i) {
        return inkline::Camera::perspective(orbit_eye(t, arc * i / frames), t.bounds.center(), {0, 1, 0}, 30.0, 1024, 768);
    };
    inkline::ViewSession a(*m, o), b(*m, o);
    std::size_t edges[2] = {0, 0};
    double seconds[2][2] = {{0, 0}, {0, 0}};  // per thread: features, visibility
    const auto view = [&](inkline::ViewSession& s, int i, int k) {
        const inkline::View& v = s.render(camera(i));
        edges[k] += v.features.silhouette_edges.size();
        seconds[k][0] += s.seconds_features();
        seconds[k][1] += v.drawing.stats.seconds_visibility;
    };
    // Each session's first view (exhaustive, and the lazy indexes) before the clock starts.
    a.render(camera(lanes == 1 ? 0 : -1));
    if (lanes == 2) b.render(camera(0));
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    if (lanes == 1) {
        for (int i = 1; i <= frames; ++i) view(a, i, 0);
    } else {  // views 1, 3, 5, ... on one thread, 2, 4, ... on the other
        std::thread other([&] {
            for (int i = 2; i <= frames; i += 2) view(b, i, 1);
        });
        for (int i = 1; i <= frames; i += 2) view(a, i, 0);
        other.join();
    }
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    std::printf("%s, %s finder, %d view%s at once: %d views in %.3f s, %.1f views/s, %.2f ms a view (features %.2f, "
                "visibility %.2f on a view's clock); silhouette edges %zu\n",
                name.c_str(), finder.c_str(), lanes, lanes > 1 ? "s" : "", frames, wall, frames / wall,
                1e3 * wall / frames, 1e3 * (seconds[0][0] + seconds[1][0]) / frames,
                1e3 * (seconds[0][1] + seconds[1][1]) / frames, edges[0] + edges[1]);
    return 0;
}
