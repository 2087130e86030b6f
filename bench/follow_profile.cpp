// The coherent finder along the bench's orbit with cold caches between views, as the pipeline
// runs it (visibility reads tens of megabytes between two searches; here a 64 MB buffer is read):
// search ms per view (mean, median, mean of the views that kept the band and of those that rebuilt
// it, the first rebuild apart: it allocates the band), the band's mean size. The first view is the
// exhaustive scan (not counted). Usage: taskset -c 1 follow_profile [mesh (armadillo@2)] [views
// (960)] [degrees per view (0.25)] [band steps (0: auto)]
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_models.hpp"
#include "features/features.hpp"

int main(int argc, char** argv) {
    const std::string name = argc > 1 ? argv[1] : "armadillo@2";
    const int views = argc > 2 ? std::max(2, std::stoi(argv[2])) : 960;
    const double dpf = argc > 3 ? std::stod(argv[3]) : 0.25;
    inkline::FinderOptions o;
    o.kind = inkline::FinderKind::Randomized;
    o.fraction = 0.0005;
    o.first_full = true;
    if (argc > 4) o.band_steps = std::stod(argv[4]);
    const inkline::Model* m = bench_model_for(name, "follow_profile");
    if (!m) return 1;
    const inkline::MeshTopology& t = m->topology();
    inkline::SilhouetteFinder finder(t, o);
    inkline::Features f;
    inkline::FeatureOptions fo;
    std::vector<unsigned char> junk(std::size_t(64) << 20, 1);
    volatile unsigned long sink = 0;
    std::vector<double> all, kept, rebuilt;
    double band = 0.0, first_rebuild = 0.0;
    for (int i = 0; i < views; ++i) {
        unsigned long s = 0;
        for (std::size_t k = 0; k < junk.size(); k += 64) s += junk[k];
        sink = sink + s;
        const auto cam = inkline::Camera::perspective(orbit_eye(t, i * dpf), t.bounds.center(), {0, 1, 0}, 30.0, 1024, 1024);
        finder.find(cam, fo, f);
        if (i == 0) continue;
        const double ms = 1e3 * f.stats.seconds_search;
        all.push_back(ms);
        (f.stats.band_rebuilt ? rebuilt : kept).push_back(ms);
        if (f.stats.band_rebuilt && i == 1) rebuilt.pop_back(), first_rebuild = ms;
        band += double(f.stats.band_faces);
    }
    auto mean = [](const std::vector<double>& v) {
        double s = 0.0;
        for (double x : v) s += x;
        return v.empty() ? 0.0 : s / double(v.size());
    };
    const double avg = mean(all);
    std::nth_element(all.begin(), all.begin() + std::ptrdiff_t(all.size() / 2), all.end());
    std::printf("%s %d views %.3g deg/view steps %g: mean %.4f median %.4f kept %.4f (%zu) rebuilt %.4f (%zu, the first %.3f) band %.0f\n",
                name.c_str(), views - 1, dpf, o.band_steps, avg, all[all.size() / 2], mean(kept), kept.size(),
                mean(rebuilt), rebuilt.size(), first_rebuild, band / double(views - 1));
    return 0;
}
