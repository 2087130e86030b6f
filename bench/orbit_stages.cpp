// The exact frame's stages along the bench's orbit (issue 46 item 1, option (b)): per mesh, one
// ViewSession (exact visibility, visible lines: as bench_frame's frame_appel_session), views every
// STEP degrees, each frame's process CPU time and the drawing's stage times (search, cusps +
// chaining, pieces, propagation, walks, ray tests). The floor of a frame that carries QI from the
// previous view is what it must still do to know the view: features and pieces (vertex images,
// the crossings it compares, the cuts); the rest (assign_qi_appel) is what it could skip at best.
// Speed-up bounds (columns): "static camera" = stages / floor (every cluster carried, nothing to
// re-decide); "walks+rays only" = the walks and ray tests skipped, propagation kept (a cluster's
// base QI carried instead of decided); "along this orbit" = the skippable share scaled by the share
// of pieces whose curve kept its signature (its mesh edges and the occluder edges it crosses, in
// order) from the previous view: only those could keep their pieces' QI. Each bound takes the
// carrying and its checks as free.
// The stage times are the drawing's (wall clocks): a row is trusted when "stages ms" is within a
// few percent of the frame's CPU time (no other process took the core meanwhile).
// Usage: orbit_stages [--meshes=a,b,...] [--step=DEG] [--frames=N] [--threads=N] [--no-signatures]
// Prints a markdown table, one row per mesh (means over the frames, the first, cold, left out).
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <sstream>
#include <string>
#include <unordered_set>
#include <vector>

#include "bench_models.hpp"
#include "pipeline.hpp"

namespace {

using namespace inkline;

bool g_signatures = true;  // --no-signatures: only the frames run (for perf: no other pieces built)

// Per curve of the view: a hash of its mesh edges and of the occluder edges it crosses, in order
// (what a carried QI compares: a curve with the same signature is cut at the same crossings into
// the same pieces and links; only their cut points move).
std::vector<std::uint64_t> curve_signatures(const Features& f, const PieceGraph& g) {
    auto mix = [](std::uint64_t h, std::uint64_t x) {
        h ^= x + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
        return h * 0xff51afd7ed558ccdULL;
    };
    std::vector<std::uint64_t> h(f.curves.size(), 0);
    for (std::size_t c = 0; c < f.curves.size(); ++c) {
        h[c] = mix(1, std::uint64_t(f.curves[c].kind));
        for (std::uint32_t e : f.curves[c].edges) h[c] = mix(h[c], e);
    }
    for (const auto& lc : g.link_crossings) {
        const std::uint32_t c = g.curves.pieces[g.links[lc.link].before].curve;
        h[c] = mix(h[c], (std::uint64_t(lc.occluder_edge) << 1) | 1);
    }
    return h;
}

struct Carry {
    double curves = 0, same_curves = 0, pieces = 0, same_pieces = 0;
};

// Shares of the curves (and of their pieces) whose signature was in the previous view.
Carry carried_share(const Features& f, const PieceGraph& g, std::unordered_set<std::uint64_t>& previous) {
    const auto h = curve_signatures(f, g);
    std::vector<std::uint32_t> pieces(h.size(), 0);
    for (const auto& p : g.curves.pieces) ++pieces[p.curve];
    Carry c;
    for (std::size_t i = 0; i < h.size(); ++i) {
        const bool same = previous.count(h[i]) > 0;
        c.curves += 1, c.same_curves += same;
        c.pieces += pieces[i], c.same_pieces += same ? pieces[i] : 0;
    }
    previous.clear();
    previous.insert(h.begin(), h.end());
    return c;
}

struct Sums {
    double cpu = 0, search = 0, chain = 0, pieces = 0, propagation = 0, walks = 0, rays = 0;
    double clusters = 0, walks_n = 0, rays_n = 0;
};

void run_mesh(const std::string& name, double step, int frames, int threads) {
    const Model* m = bench_model_for(name, "orbit_stages");
    if (!m) return;
    m->rays();
    const auto& cuts = m->self_intersections().cuts;
    ViewOptions opt;
    opt.exact_hidden = false;
    opt.threads = threads;
    ViewSession session(*m, opt);
    const auto& t = m->topology();
    auto cam_at = [&](int i) {
        Camera c = Camera::perspective(orbit_eye(t, step * i), t.bounds.center(), {0, 1, 0}, 30.0, 1024, 1024);
        c.set_near(default_near(t));
        return c;
    };
    PieceGraph g;  // the signatures' own pieces (untimed)
    std::unordered_set<std::uint64_t> previous;
    session.render(cam_at(0));  // cold: storage grows
    if (g_signatures) {
        build_pieces(g, t, session.render(cam_at(0)).features, cam_at(0), &cuts, 1);
        carried_share(session.render(cam_at(0)).features, g, previous);
    }
    Sums s;
    Carry carry;
    for (int i = 1; i <= frames; ++i) {
        const double c0 = process_cpu_ms();
        const View& v = session.render(cam_at(i));
        s.cpu += process_cpu_ms() - c0;
        const auto& d = v.drawing.stats;
        s.search += 1e3 * v.features.stats.seconds_search;
        s.chain += 1e3 * v.features.stats.seconds_chain;
        s.pieces += 1e3 * d.seconds_pieces;
        s.propagation += 1e3 * d.seconds_propagation;
        s.walks += 1e3 * d.seconds_walks;
        s.rays += 1e3 * d.seconds_ray_tests;
        s.clusters += double(d.clusters);
        s.walks_n += double(d.walks);
        s.rays_n += double(d.ray_tests);
        if (!g_signatures) continue;
        build_pieces(g, t, v.features, cam_at(i), &cuts, 1);
        const Carry c = carried_share(v.features, g, previous);
        carry.curves += c.curves, carry.same_curves += c.same_curves;
        carry.pieces += c.pieces, carry.same_pieces += c.same_pieces;
    }
    const double n = frames;
    const double stages = (s.search + s.chain + s.pieces + s.propagation + s.walks + s.rays) / n;
    const double floor_ms = (s.search + s.chain + s.pieces) / n;
    const double skip = (s.propagation + s.walks + s.rays) / n;
    const double carried = carry.same_pieces / std::max(1.0, carry.pieces);
    auto pct = [&](double x) { return 100.0 * x / n / stages; };
    std::printf("| %s | %.3f | %.3f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f / %.0f / %.1f | %.3f | %.0f | "
                "%.2fx | %.2fx | %.0f | %.2fx |\n",
                name.c_str(), s.cpu / n, stages, pct(s.search), pct(s.chain), pct(s.pieces), pct(s.propagation),
                pct(s.walks), pct(s.rays), s.clusters / n, s.walks_n / n, s.rays_n / n, floor_ms, 100.0 * skip / stages,
                stages / floor_ms, stages / (stages - (s.walks + s.rays) / n), 100.0 * carried,
                stages / (stages - carried * skip));
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> meshes{"fandisk", "bunny00", "knot1", "armadillo", "elephant", "ChineseDragon-10kv"};
    double step = 6.0;
    int frames = 30, threads = 1;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a.rfind("--meshes=", 0) == 0) meshes = split_commas(a.substr(9));
        else if (a.rfind("--step=", 0) == 0) step = std::stod(a.substr(7));
        else if (a.rfind("--frames=", 0) == 0) frames = std::max(1, std::stoi(a.substr(9)));
        else if (a == "--no-signatures") g_signatures = false;
        else if (a.rfind("--threads=", 0) == 0) threads = std::max(1, std::stoi(a.substr(10)));
        else {
            std::fprintf(stderr, "orbit_stages: unknown argument '%s'\n", a.c_str());
            return 2;
        }
    }
    std::printf("Orbit %g deg/frame, %d frames after a cold one, 1024 x 1024, %d thread(s).\n\n", step, frames,
                threads);
    std::printf("| mesh | frame CPU ms | stages ms | search %% | cusps+chain %% | pieces %% | propagation %% | "
                "walks %% | rays %% | clusters / walks / rays | floor ms | skippable %% | static camera | "
                "walks+rays only | pieces on unchanged curves %% | along this orbit |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const auto& m : meshes) run_mesh(m, step, frames, threads);
    return 0;
}
