// Agreement of estimate_curvature (Rusinkiewicz's per-face fit) with CGAL's jet fitting
// (CGAL/Monge_via_jet_fitting.h, Cazals and Pouget) on the sample meshes: at each vertex a jet of
// degree 2 and, separately, of degree 4 fitted to the vertex and its 2-ring (its neighbours and
// theirs), Monge form of degree 2, oriented by our normal. Prints a markdown table (bench/results/
// curvature.md through bench/run_curvature.sh): per mesh the median and 95th percentile of the
// relative difference of k1 and of k2, where
//     rel(a, b) = |a - b| / max(|a|, |b|, k_typ),
// k_typ being the mesh's typical curvature, the median over vertices of sqrt((k1^2 + k2^2) / 2) by
// our estimate: without that floor, flat regions (k near 0 in both) would divide noise by noise.
// Vertices compared: those our estimate marks valid and whose 2-ring has enough points for the jet
// (6 for degree 2, 15 for degree 4). Usage: curvature_agreement [mesh ...] (names in
// INKLINE_DATA_DIR/meshes, without .off).
#include <CGAL/Monge_via_jet_fitting.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_models.hpp"
#include "curvature/curvature.hpp"
#include "pipeline.hpp"

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Jet = CGAL::Monge_via_jet_fitting<Kernel>;

// The vertex first (the jet's origin), then its 2-ring; `stamp` marks vertices already taken.
void two_ring(const inkline::MeshTopology& t, std::uint32_t v, std::vector<std::uint32_t>& stamp, std::uint32_t mark,
              std::vector<std::uint32_t>& out) {
    out.clear();
    out.push_back(v);
    stamp[v] = mark;
    for (int ring = 0, from = 0; ring < 2; ++ring) {
        const int to = int(out.size());
        for (int k = from; k < to; ++k) {
            const std::uint32_t a = out[std::size_t(k)];
            for (std::uint32_t i = t.vertex_edge_begin[a]; i < t.vertex_edge_begin[a + 1]; ++i) {
                const auto& ev = t.edge_vertex[t.vertex_edges[i]];
                const std::uint32_t b = ev[0] == a ? ev[1] : ev[0];
                if (stamp[b] != mark) stamp[b] = mark, out.push_back(b);
            }
        }
        from = to;
    }
}

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return NAN;
    const std::size_t i = std::min(v.size() - 1, std::size_t(q * double(v.size())));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(i), v.end());
    return v[i];
}

struct Agreement {
    std::vector<double> rel_k1, rel_k2;
};

void compare_mesh(const std::string& name) {
    const inkline::Model* m = bench_model_for(name, "curvature_agreement");
    if (!m) return;
    const inkline::MeshTopology& t = m->topology();
    const inkline::CurvatureField& f = m->curvature();
    std::vector<double> mag;
    for (std::size_t i = 0; i < f.size(); ++i)
        if (f.valid[i]) mag.push_back(std::sqrt(0.5 * (double(f.k1[i]) * f.k1[i] + double(f.k2[i]) * f.k2[i])));
    const double k_typ = quantile(mag, 0.5);
    auto rel = [&](double a, double b) { return std::abs(a - b) / std::max({std::abs(a), std::abs(b), k_typ}); };

    Agreement deg[2];
    std::vector<std::uint32_t> stamp(t.vertex_count(), 0), ring;
    std::vector<Kernel::Point_3> pts;
    for (std::uint32_t v = 0; v < t.vertex_count(); ++v) {
        if (!f.valid[v]) continue;
        two_ring(t, v, stamp, v + 1, ring);
        pts.clear();
        for (auto u : ring) pts.emplace_back(t.positions[u].x, t.positions[u].y, t.positions[u].z);
        const glm::vec3 n = f.normal[v];
        for (int d = 0; d < 2; ++d) {
            const std::size_t degree = d == 0 ? 2 : 4;
            if (pts.size() < (degree + 1) * (degree + 2) / 2) continue;
            Jet fit;
            Jet::Monge_form monge = fit(pts.begin(), pts.end(), degree, 2);
            monge.comply_wrt_given_normal(Kernel::Vector_3(n.x, n.y, n.z));
            // CGAL's Monge form is z = (k_max x^2 + k_min y^2) / 2 along the normal: bending away from
            // the normal is negative there, positive here, so ours are minus theirs, order reversed.
            const double k1 = -monge.principal_curvatures(1), k2 = -monge.principal_curvatures(0);
            deg[d].rel_k1.push_back(rel(f.k1[v], k1));
            deg[d].rel_k2.push_back(rel(f.k2[v], k2));
        }
    }
    std::printf("| %s | %zu | %zu | %.3g |", name.c_str(), t.vertex_count(), f.invalid_vertices, k_typ * f.feature_size);
    for (const Agreement& a : deg)
        std::printf(" %zu | %.3f | %.3f | %.3f | %.3f |", a.rel_k1.size(), quantile(a.rel_k1, 0.5),
                    quantile(a.rel_k1, 0.95), quantile(a.rel_k2, 0.5), quantile(a.rel_k2, 0.95));
    std::printf("\n");
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> meshes(argv + 1, argv + argc);
    if (meshes.empty())
        meshes = {"bunny00", "armadillo", "elephant", "fandisk", "knot1", "ChineseDragon-10kv",
                  "blobby",  "cow",       "eight",    "larger_sphere", "ellipsoid"};
    std::printf("| mesh | vertices | invalid | k_typ x feature size | deg 2: compared | k1 median | k1 p95 | "
                "k2 median | k2 p95 | deg 4: compared | k1 median | k1 p95 | k2 median | k2 p95 |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const auto& name : meshes) compare_mesh(name);
    return 0;
}
