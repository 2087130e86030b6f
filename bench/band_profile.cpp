// A harness for the coherence band's rebuild pass alone (FacingBand::select over the face blocks,
// as SilhouetteFinder::build_band runs it): for a range of limits, the mean wall time of one pass with
// cold caches (a 64 MB buffer is read between passes, as a rebuild follows views that read other
// memory), the share of the float planes it reads and the share of faces it selects, over 24 eyes
// on the bench's orbit (20 degrees above the equator at the framing distance). Also the time to
// stream every plane once (a plain sum, the memory's bound for a pass that reads them all).
// Usage: band_profile [mesh (default armadillo@2)] [repeats (default 4)]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench_models.hpp"
#include "features/facing.hpp"

int main(int argc, char** argv) {
    const std::string name = argc > 1 ? argv[1] : "armadillo@2";
    const int repeats = argc > 2 ? std::max(1, std::stoi(argv[2])) : 4;
    const inkline::Model* m = bench_model_for(name, "band_profile");
    if (!m) return 1;
    const inkline::MeshTopology& t = m->topology();
    const std::size_t nf = t.face_count();
    inkline::FaceBlocks blocks;
    blocks.build(t);
    std::vector<unsigned char> junk(std::size_t(64) << 20, 1);
    volatile unsigned long sink = 0;
    auto evict = [&] {
        unsigned long s = 0;
        for (std::size_t i = 0; i < junk.size(); i += 64) s += junk[i];
        sink = sink + s;
    };
    auto now = [] { return std::chrono::steady_clock::now(); };
    auto ms = [](auto a, auto b) { return 1e3 * std::chrono::duration<double>(b - a).count(); };
    {
        double total = 0.0;
        for (int r = 0; r < repeats * 4; ++r) {
            evict();
            const auto t0 = now();
            // (an integer sum of the bits, which the compiler vectorizes: no chain of dependent
            // float additions bounds the loop)
            std::uint32_t s = 0;
            for (const auto& p : t.facing) {
                std::uint32_t w[4];
                std::memcpy(w, &p, sizeof(w));
                s += w[0] + w[1] + w[2] + w[3];
            }
            total += ms(t0, now());
            sink = sink + s;  // (the sum is used: the loop stays)
        }
        std::printf("%s: %zu faces; streaming every plane (%.1f MB): %.3f ms\n", name.c_str(), nf,
                    double(nf * sizeof(inkline::MeshTopology::FacingPlane)) / 1e6, total / (repeats * 4));
    }
    const double R = t.bounds.half_diagonal();
    inkline::FacingBand band;
    std::vector<std::uint64_t> front(nf / 64 + 1);
    std::printf("| limit / R | ms per pass | planes read | faces selected |\n|---:|---:|---:|---:|\n");
    for (double limit : {0.0, 0.05, 0.1, 0.2, 0.4, 0.8}) {
        double total = 0.0, read = 0.0, selected = 0.0;
        int n = 0;
        for (int r = 0; r < repeats; ++r)
            for (int deg = 0; deg < 360; deg += 15, ++n) {
                const glm::dvec3 e = orbit_eye(t, deg) - t.facing_origin;
                const double ev[3] = {e.x, e.y, e.z};
                inkline::FacingFilter f;
                f.bind(t, ev, 1.0);
                evict();
                const auto t0 = now();
                read += double(band.select(t, f, float(limit * R), &blocks, front.data()));
                total += ms(t0, now());
                selected += double(band.size());
            }
        std::printf("| %.2f | %.3f | %.3f | %.3f |\n", limit, total / n, read / n / double(nf), selected / n / double(nf));
    }
    return 0;
}
