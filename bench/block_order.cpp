// How tight the face blocks would be in another face order: the share of planes a coherence band
// rebuild reads (faces in 64-face blocks whose range of distances straddles the band's margin, the
// box bound of FaceBlocks) for 8 eyes of the bench's orbit, the margin set so that the band holds
// 4.4 % of the faces (a 1 deg/frame band on armadillo@2). Orders: the mesh's own (a Hilbert curve
// of the vertices, src/model/reorder.cpp), and a 6D Morton order of the faces' centroids (over the
// largest extent of the box) and unit normals (times a weight), 10 bits a coordinate.
// Usage: block_order [mesh (default armadillo@2)]
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

#include "bench_models.hpp"
#include "features/facing.hpp"

namespace {
std::uint64_t spread6(std::uint32_t x) {  // bit i of x (10 bits) to bit 6 i
    std::uint64_t r = 0;
    for (int i = 0; i < 10; ++i) r |= std::uint64_t((x >> i) & 1) << (6 * i);
    return r;
}
}  // namespace

int main(int argc, char** argv) {
    const std::string name = argc > 1 ? argv[1] : "armadillo@2";
    const inkline::Model* m = bench_model_for(name, "block_order");
    if (!m) return 1;
    const inkline::MeshTopology& t = m->topology();
    const std::size_t nf = t.face_count();
    constexpr std::size_t kBlock = 64;
    const glm::dvec3 lo = t.bounds.lo, hi = t.bounds.hi;
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-300});
    // The eyes and margins.
    std::vector<inkline::FacingFilter> eyes;
    std::vector<float> margins;
    std::vector<float> dist(nf);
    for (int deg = 0; deg < 360; deg += 45) {
        const glm::dvec3 e = orbit_eye(t, deg) - t.facing_origin;
        const double ev[3] = {e.x, e.y, e.z};
        inkline::FacingFilter f;
        f.bind(t, ev, 1.0);
        for (std::size_t i = 0; i < nf; ++i) dist[i] = std::abs(f.signed_distance(t.facing[i]));
        const std::size_t k = nf * 44 / 1000;
        std::nth_element(dist.begin(), dist.begin() + std::ptrdiff_t(k), dist.end());
        eyes.push_back(f);
        margins.push_back(dist[k]);
    }
    auto share_read = [&](const std::vector<std::uint32_t>& order) {
        double sum = 0.0;
        for (std::size_t v = 0; v < eyes.size(); ++v) {
            const double ev[4] = {eyes[v].ex, eyes[v].ey, eyes[v].ez, -double(eyes[v].w)};
            std::size_t read = 0;
            for (std::size_t b = 0; b < nf; b += kBlock) {
                const std::size_t b1 = std::min(nf, b + kBlock);
                float l[4] = {INFINITY, INFINITY, INFINITY, INFINITY}, h[4] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
                for (std::size_t i = b; i < b1; ++i) {
                    const auto& p = t.facing[order[i]];
                    const float x[4] = {p.nx, p.ny, p.nz, p.d};
                    for (int k = 0; k < 4; ++k) l[k] = std::min(l[k], x[k]), h[k] = std::max(h[k], x[k]);
                }
                double rl = 0.0, rh = 0.0;
                for (int k = 0; k < 4; ++k) {
                    const double a = ev[k] * l[k], c = ev[k] * h[k];
                    rl += std::min(a, c), rh += std::max(a, c);
                }
                if (!(rl > margins[v] || rh < -margins[v])) read += b1 - b;  // (NaN: read)
            }
            sum += double(read) / double(nf);
        }
        return sum / double(eyes.size());
    };
    std::vector<std::uint32_t> order(nf);
    std::iota(order.begin(), order.end(), 0u);
    std::printf("%s: %zu faces, %zu-face blocks, a band of 4.4 %% of the faces, 8 eyes\n", name.c_str(), nf, kBlock);
    std::printf("| order | planes read |\n|---|---:|\n| the mesh's (Hilbert) | %.3f |\n", share_read(order));
    std::vector<std::uint64_t> key(nf);
    for (double w : {0.0, 0.25, 0.5, 1.0, 2.0, 4.0}) {
        const double s = std::max(1.0, w);  // the six coordinates in [0, 1]
        for (std::size_t f = 0; f < nf; ++f) {
            const auto& c = t.faces[f];
            const glm::dvec3 g = (t.positions[c[0]] + t.positions[c[1]] + t.positions[c[2]]) / 3.0;
            const auto& p = t.facing[f];
            const double x[6] = {(g.x - lo.x) / extent / s, (g.y - lo.y) / extent / s, (g.z - lo.z) / extent / s,
                                 w * (p.nx + 1.0) / 2.0 / s, w * (p.ny + 1.0) / 2.0 / s, w * (p.nz + 1.0) / 2.0 / s};
            std::uint64_t k = 0;
            for (int i = 0; i < 6; ++i)
                k |= spread6(std::uint32_t((std::isfinite(x[i]) ? std::clamp(x[i], 0.0, 1.0) : 0.0) * 1023.0)) << i;
            key[f] = k;
        }
        std::iota(order.begin(), order.end(), 0u);
        std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
        std::printf("| 6D Morton, normal weight %.2f | %.3f |\n", w, share_read(order));
    }
    return 0;
}
