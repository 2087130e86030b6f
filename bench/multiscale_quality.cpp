// The multi-scale levels' quality figures that tests/test_detail.cpp bounds, in one run: turned-over
// faces of the default (umbrella, r = 1/2) levels of armadillo, M3's mean and median |k1| against
// M0's for the second-order levels (armadillo, bunny00) and the thin-guarded ones (armadillo), and
// issue 43's density growth along the dolly (detail over plain) for armadillo, elephant, bunny00
// and the thin-guarded armadillo; each figure beside its test's bound. --shuffle=SEED renumbers
// every model first (vertices and faces permuted, corners rotated), to see a figure's dependence on
// the numbering. Prints Markdown.
// Usage: multiscale_quality [--shuffle=SEED] [--sweeps=N] [--tangential=N] [--spread=S] [--kinds]
// (--sweeps, --tangential, --spread: the default levels' options; --kinds: the 8x drawings' lengths
// by kind). bench/results/multiscale_order.md has its runs.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <numeric>
#include <random>
#include <string>

#include <glm/geometric.hpp>

#include "core/clock.hpp"
#include "detail/multiscale.hpp"
#include "test_data.hpp"

namespace {

using namespace inkline;

bool kinds = false;  // --kinds

std::unique_ptr<Model> load(const std::string& name, unsigned shuffle) {
    auto model = std::make_unique<Model>(Model::load(test::mesh_path(name)));
    if (shuffle == 0) return model;
    const MeshTopology& m = model->topology();
    std::mt19937 rng(shuffle);
    std::vector<std::uint32_t> to(m.vertex_count());
    std::iota(to.begin(), to.end(), 0u);
    std::shuffle(to.begin(), to.end(), rng);
    TriangleMesh t;
    t.positions.resize(m.vertex_count());
    for (std::size_t v = 0; v < to.size(); ++v) t.positions[to[v]] = m.positions[v];
    for (const auto& f : m.faces) {
        const unsigned k = rng() % 3;
        t.triangles.push_back({to[f[k]], to[f[(k + 1) % 3]], to[f[(k + 2) % 3]]});
    }
    std::shuffle(t.triangles.begin(), t.triangles.end(), rng);
    return std::make_unique<Model>(std::move(t));
}

std::size_t turned_over(const Model& model, const MultiscaleLevels& L, int k) {
    const MeshTopology& m0 = model.topology();
    const auto p = level_positions(model, L, k);
    std::size_t n = 0;
    for (std::uint32_t f = 0; f < m0.face_count(); ++f) {
        const auto& v = m0.faces[f];
        n += glm::dot(glm::cross(p[v[1]] - p[v[0]], p[v[2]] - p[v[0]]), m0.face_normal(f)) < 0.0;
    }
    return n;
}

double density_ratio(const Model& model, const MultiscaleLevels& L) {
    ViewOptions o;
    o.features.kinds[int(LineKind::Crease)] = false;
    o.surface.suggestive = true;
    const MeshTopology& m = model.topology();
    const Camera framed = test::framed_camera(m.bounds, 1024);
    const double target = L.feature_size * framed.focal() / glm::length(framed.eye() - m.bounds.center());
    MultiscaleSession s(model, L, o, {.target_px = target});
    ViewSession plain(model, o);
    const test::DollyDensity g = test::dolly_density(
        m.bounds, framed, [&](const Camera& cam) { return test::visible_length_px(plain.render(cam).drawing); },
        [&](const Camera& cam) { return test::visible_length_px(s.render(cam).drawing); });
    if (kinds) {  // lengths by kind at 8x: what is left of the drawing
        const glm::dvec3 c = m.bounds.center();
        const Camera far = Camera::perspective(c + 8.0 * (framed.eye() - c), c, {0, 1, 0}, 30.0, 1024, 1024);
        for (const Drawing* d : {&plain.render(far).drawing, &s.render(far).drawing}) {
            double by[16] = {};
            for (const Piece& p : d->pieces)
                if (p.qi == 0)
                    for (std::size_t i = 1; i < p.points.size(); ++i) by[int(p.kind)] += glm::length(p.points[i] - p.points[i - 1]);
            std::printf("  8x: silhouette %.0f border %.0f suggestive %.0f\n", by[0], by[1], by[4]);
        }
        std::printf("  start plain %.0f detail %.0f\n", g.plain_start, g.detail_start);
    }
    return g.detail_growth / g.plain_growth;
}

}  // namespace

int main(int argc, char** argv) {
    unsigned shuffle = 0;
    MultiscaleOptions plain;  // the default levels, or as the flags set them
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a.rfind("--shuffle=", 0) == 0) shuffle = unsigned(std::stoul(a.substr(10)));
        else if (a.rfind("--sweeps=", 0) == 0) plain.sweeps = std::stoi(a.substr(9));
        else if (a.rfind("--tangential=", 0) == 0) plain.tangential_sweeps = std::stoi(a.substr(13));
        else if (a.rfind("--spread=", 0) == 0) plain.spread = std::stod(a.substr(9));
        else if (a == "--kinds") kinds = true;
        else {
            std::fprintf(stderr, "multiscale_quality: unknown argument '%s'\n", a.c_str());
            return 2;
        }
    }
    const MultiscaleOptions second{.ratio = 0.75, .fairing = MultiscaleFairing::SecondOrder, .sweeps = 8, .tangential_sweeps = 32};
    const auto armadillo = load("armadillo", shuffle), bunny = load("bunny00", shuffle), elephant = load("elephant", shuffle);
    double t0 = thread_cpu_seconds();
    const MultiscaleLevels a = build_multiscale_levels(*armadillo, plain);
    const double seconds_default = thread_cpu_seconds() - t0;
    t0 = thread_cpu_seconds();
    const MultiscaleLevels a2 = build_multiscale_levels(*armadillo, second);
    const double seconds_second = thread_cpu_seconds() - t0;
    const MultiscaleLevels b2 = build_multiscale_levels(*bunny, second);
    t0 = thread_cpu_seconds();
    const MultiscaleLevels at = build_multiscale_levels(*armadillo, thin_guarded({}));
    const double seconds_thin = thread_cpu_seconds() - t0;
    const MultiscaleLevels b = build_multiscale_levels(*bunny, plain), e = build_multiscale_levels(*elephant, plain);
    std::printf("| figure | value | bound |\n|---|---:|---:|\n");
    for (int k = 1; k < 4; ++k) std::printf("| armadillo umbrella folds M%d | %zu | 104 |\n", k, turned_over(*armadillo, a, k));
    for (int k = 1; k < 4; ++k)
        std::printf("| armadillo umbrella median M%d/M0 | %.3f | 0.9 |\n", k, a.median_abs_k1[std::size_t(k)] / a.median_abs_k1[0]);
    std::printf("| armadillo second-order folds M1-M3 | %zu %zu %zu | |\n", turned_over(*armadillo, a2, 1),
                turned_over(*armadillo, a2, 2), turned_over(*armadillo, a2, 3));
    std::printf("| armadillo second-order mean M3/M0 | %.4f (%.4f) | 0.85 |\n", a2.mean_abs_k1[3] / a2.mean_abs_k1[0], a2.mean_abs_k1[3]);
    std::printf("| armadillo second-order median M3/M0 | %.4f (%.4f) | 0.75 |\n", a2.median_abs_k1[3] / a2.median_abs_k1[0], a2.median_abs_k1[3]);
    std::printf("| bunny00 second-order mean M3/M0 | %.4f (%.3f) | 0.92 |\n", b2.mean_abs_k1[3] / b2.mean_abs_k1[0], b2.mean_abs_k1[3]);
    std::printf("| armadillo thin-guarded mean M3/M0 | %.4f (%.4f) | 0.8 |\n", at.mean_abs_k1[3] / at.mean_abs_k1[0], at.mean_abs_k1[3]);
    std::printf("| density armadillo | %.3f | 0.5 |\n", density_ratio(*armadillo, a));
    std::printf("| density elephant | %.3f | 0.5 |\n", density_ratio(*elephant, e));
    std::printf("| density bunny00 | %.3f | 0.6 |\n", density_ratio(*bunny, b));
    std::printf("| density armadillo thin-guarded | %.3f | 0.5 |\n", density_ratio(*armadillo, at));
    std::printf("| CPU s: armadillo default, second-order, thin-guarded | %.3f %.3f %.3f | |\n", seconds_default, seconds_second, seconds_thin);
    std::printf("| armadillo umbrella median, mean abs k1 M0-M3 |");
    for (int k = 0; k < 4; ++k) std::printf(" %.4f %.4f", a.median_abs_k1[std::size_t(k)], a.mean_abs_k1[std::size_t(k)]);
    std::printf(" | |\n");
    return 0;
}
