// The progressive mesh's incremental front (src/detail/progressive_mesh_front.hpp) frame by frame:
// hierarchy build time and memory beside the multi-scale method's pre-process on the same model,
// then the adaptation's cost a frame (the thread's CPU time: one core) along a slow dolly and an
// orbit, with and without geomorphs (the largest per-frame vertex move they make, in pixels).
// Not a test: numbers go to bench/results/detail_methods.md (bench/run_detail.sh).
//
//   pm_frames [MESH[@N]] [PX] [--no-multiscale] [--path=dolly|orbit|dolly-in] [--geomorphs=on|off]
//             [--whole[=FRAMES]] [--budget=N|lag|lag:BASE:FRAMES:MOST[,...]] [--per-frame]
//   (defaults armadillo 3, both paths, both with and without geomorphs)
//
// --budget: a front for each of the front's budgets a frame, their frames interleaved: N a fixed
// one (FrontBudget::fixed(N); 0: none, the front's default), lag the lag-following rule
// (FrontBudget::following_lag), lag:BASE:FRAMES:MOST another such rule; with the frames that
// deferred work and, at the last view held still, the frames until nothing is
// deferred; --per-frame: one line a frame on stderr ("run B frame K": the B-th budget's ms,
// operations, deferred, backlog, budget, triangles, RSS; with --whole: each session's frame ms,
// adaptation ms, triangles).
//
// --whole: the whole frame instead (PmSession, by default with the sessions' own budget, the
// lag-following rule (PmViewOptions::default_budget), as the window and `inkline bench` run it:
// adaptation with geomorphs, the adapted Model,
// curvature, smoothing, silhouettes and suggestive contours with exact visibility, as
// `inkline bench --detail`), FRAMES frames of each path (default 40), each stage's median share,
// a session per --budget, their frames interleaved, beside the multi-scale method's whole frame on
// the same cameras, each frame also in wall ms and in the CPU ms of all the process's threads
// (Embree builds on its own); with a third path, dolly-in,
// `inkline bench --path=dolly`'s (1.5 to 0.6 times the framing distance over the frames).
//
// Paths (1024 x 1024, 30 degrees): the dolly moves the eye from 1x to 4x the framed distance,
// 1 % of the distance a frame (140 frames); the orbit turns 1 degree a frame about the vertical
// axis at the framed distance (120 frames). Each path starts from a front converged at its first
// view (the cost of that is printed apart).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "bench_models.hpp"
#include "core/clock.hpp"
#include "detail/multiscale.hpp"
#include "detail/progressive_mesh_front.hpp"
#include "detail/progressive_mesh_session.hpp"
#include "pm_bench_util.hpp"

using namespace inkline;
using inkline::bench::status_mib;
using inkline::thread_cpu_seconds;

namespace {

Camera path_camera(const MeshTopology& t, double times, double yaw_deg) {
    const Camera framed = Camera::framing(t.bounds, 1024, 1024);
    const glm::dvec3 c = t.bounds.center(), d = framed.eye() - c;
    const double a = yaw_deg * M_PI / 180.0;
    const glm::dvec3 turned{std::cos(a) * d.x + std::sin(a) * d.z, d.y, -std::sin(a) * d.x + std::cos(a) * d.z};
    return Camera::perspective(c + times * turned, c, framed.up(), framed.fov_deg(), 1024, 1024);
}

// `inkline bench --path=dolly`'s camera k of `frames`: from 1.5 to 0.6 times the framing distance
// along the default view direction.
Camera bench_dolly_camera(const MeshTopology& t, int k, int frames) {
    const double fov = 30.0, D = t.bounds.half_diagonal() / std::sin(fov * M_PI / 360.0);
    const glm::dvec3 dir = glm::normalize(glm::dvec3(1.0, 0.6, 1.4));
    const double s = 1.5 - 0.9 * double(k) / double(std::max(1, frames - 1));
    return Camera::perspective(t.bounds.center() + s * D * dir, t.bounds.center(), {0, 1, 0}, fov, 1024, 1024);
}

struct PathResult {
    std::vector<double> ms;
    double most_ms = 0.0, largest_move_px = 0.0, converge_ms = 0.0;
    std::size_t splits = 0, collapses = 0, frames = 0, tri_first = 0, tri_last = 0, most_ops = 0;
    std::size_t bytes_first = 0, bytes_last = 0, bytes_most = 0;  // the front's storage (AdaptiveFront::bytes)
    std::size_t deferring_frames = 0, longest_deferring = 0, catch_up_frames = 0, most_deferred = 0;
    std::uint64_t last_mesh_hash = 0;  // the last frame's triangles (FNV-1a): a change of the code that
                                       // should not change the mesh shows here
};

std::uint64_t triangles_hash(const TriangleMesh& m) {
    std::uint64_t h = 1469598103934665603ull;
    const auto* bytes = reinterpret_cast<const unsigned char*>(m.triangles.data());
    for (std::size_t j = 0; j < m.triangles.size() * sizeof(m.triangles[0]); ++j) h = (h ^ bytes[j]) * 1099511628211ull;
    return h;
}

// --budget's words: N (a fixed budget; 0: none), lag (FrontBudget::following_lag) or
// lag:BASE:FRAMES:MOST.
FrontBudget parse_budget(const std::string& word) {
    if (word == "lag") return FrontBudget::following_lag();
    if (word.rfind("lag:", 0) == 0) {
        FrontBudget b;
        if (std::sscanf(word.c_str(), "lag:%zu:%zu:%zu", &b.base, &b.catch_up_frames, &b.most) == 3) return b;
        std::fprintf(stderr, "pm_frames: --budget: %s is not lag:BASE:FRAMES:MOST\n", word.c_str());
        std::exit(2);
    }
    const long long n = std::atoll(word.c_str());
    return n > 0 ? FrontBudget::fixed(std::size_t(n)) : FrontBudget::none();
}

std::string budget_name(const FrontBudget& b) {
    if (!b.budgeted()) return "none";
    if (b.base == b.most) return std::to_string(b.base);
    return std::to_string(b.base) + " + backlog / " + std::to_string(b.catch_up_frames) + ", at most " +
           std::to_string(b.most);
}

// The front along a path, a front per budget, their frames interleaved (frame k of each, then
// frame k + 1) so that a shared machine's load changes weigh on each alike.
std::vector<PathResult> run_path(const ProgressiveMesh& pm, const MeshTopology& t, const DetailCriterion& c, bool dolly,
                                 bool geomorphs, const std::vector<FrontBudget>& budgets, bool per_frame) {
    const int frames = dolly ? 140 : 120;
    const auto camera_at = [&](int k) {
        return dolly ? path_camera(t, std::pow(1.01, k), 0.0) : path_camera(t, 1.0, double(k));
    };
    std::vector<std::unique_ptr<AdaptiveFront>> fronts;
    std::vector<PathResult> results(budgets.size());
    for (PathResult& r : results) {
        fronts.push_back(std::make_unique<AdaptiveFront>(pm, GeomorphOptions{.enabled = geomorphs}));
        AdaptiveFront& front = *fronts.back();
        const double c0 = thread_cpu_seconds();
        for (int k = 0; k < 50; ++k) {  // converge at the first view (operations made at once there)
            const FrontStats s = front.update(camera_at(0), c, 10.0);
            if (s.splits + s.collapses + s.morphs_running == 0) break;
        }
        r.converge_ms = (thread_cpu_seconds() - c0) * 1e3;
        r.tri_first = front.active_faces();
        r.bytes_first = r.bytes_most = front.bytes();
    }
    std::vector<std::size_t> deferring_run(budgets.size(), 0);
    for (int k = 1; k <= frames; ++k)
        for (std::size_t b = 0; b < budgets.size(); ++b) {
            AdaptiveFront& front = *fronts[b];
            PathResult& r = results[b];
            const Camera cam = camera_at(k);
            const double t0 = thread_cpu_seconds();
            const FrontStats s = front.update(cam, c, 1.0 / 25.0, budgets[b]);
            const double ms = (thread_cpu_seconds() - t0) * 1e3;
            if (per_frame)
                std::fprintf(stderr, "run %zu frame %d %.3f ms: %zu splits %zu collapses %zu started %zu ended %zu running %zu tried "
                             "%zu deferred %zu triangles %.0f MiB RSS %zu backlog %lld budget\n",
                             b, k, ms, s.splits, s.collapses, s.morphs_started, s.morphs_ended, s.morphs_running, s.tried,
                             s.deferred, s.triangles, status_mib("VmRSS"), s.backlog,
                             s.budget == SIZE_MAX ? -1ll : (long long)s.budget);
            deferring_run[b] = s.deferred ? deferring_run[b] + 1 : 0;
            r.deferring_frames += s.deferred > 0;
            r.longest_deferring = std::max(r.longest_deferring, deferring_run[b]);
            r.most_deferred = std::max(r.most_deferred, s.deferred);
            r.ms.push_back(ms);
            r.most_ms = std::max(r.most_ms, ms);
            r.splits += s.splits;
            r.collapses += s.collapses;
            r.most_ops = std::max(r.most_ops, s.splits + s.collapses);
            r.largest_move_px = std::max(r.largest_move_px, s.largest_move_px);
            r.bytes_most = std::max(r.bytes_most, front.bytes());
        }
    for (std::size_t b = 0; b < budgets.size(); ++b) {
        AdaptiveFront& front = *fronts[b];
        PathResult& r = results[b];
        r.bytes_last = front.bytes();
        r.frames = std::size_t(frames);
        r.tri_last = front.active_faces();
        r.last_mesh_hash = triangles_hash(front.mesh());
        // (the last view held still: the frames until the budget leaves nothing for later)
        for (std::size_t deferred = r.most_deferred ? 1 : 0; deferred && r.catch_up_frames < 200; ++r.catch_up_frames)
            deferred = front.update(camera_at(frames), c, 1.0 / 25.0, budgets[b]).deferred;
    }
    return results;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

// bench --detail's lines: silhouettes and suggestive contours, creases off, Appel visibility.
ViewOptions whole_frame_options() {
    ViewOptions o;
    o.exact_hidden = false;
    o.surface.suggestive = true;
    o.features.kinds[int(LineKind::Crease)] = false;
    return o;
}

// One PmSession along a whole-frame path and what it measured.
struct WholeRun {
    FrontBudget budget;
    std::unique_ptr<PmSession> session;
    std::vector<double> cpu, wall, all_cpu, index_ms;
    std::vector<std::vector<double>> stage = std::vector<std::vector<double>>(11);
    std::size_t moving = 0, pierced = 0, triangles = 0, ray_tests = 0, vertices = 0, recomputed = 0, inconsistent = 0;
    std::size_t blocks = 0, rebuilt = 0, refitted = 0;  // the ray index kept across frames
};

// The whole pm frame along a path: thread CPU ms a frame (median, most) and each stage's median
// wall ms (PmFrameSeconds), a session per budget, their frames interleaved (frame k of each, then
// frame k + 1) so that a shared machine's load changes weigh on each alike; then the multi-scale
// session's whole frame on the same cameras.
void run_whole(const Model& model, const ProgressiveMesh& pm, const MultiscaleLevels* levels, double px,
               const std::string& path, int frames, const std::vector<FrontBudget>& budgets, bool per_frame) {
    const MeshTopology& t = model.topology();
    const bool dolly = path == "dolly";
    const auto camera_at = [&](int k) {
        Camera c = dolly ? path_camera(t, std::pow(1.01, k), 0.0) : path == "orbit" ? path_camera(t, 1.0, double(k))
                                                                 : bench_dolly_camera(t, k, frames);
        c.set_near(default_near(t));
        return c;
    };
    const char* path_name = dolly ? "dolly 1 %/frame" : path == "orbit" ? "orbit 1 deg/frame" : "dolly in, bench's";
    std::vector<WholeRun> runs(budgets.size());
    for (std::size_t b = 0; b < budgets.size(); ++b) {
        PmViewOptions options = PmViewOptions::for_path(model, px);
        options.budget = runs[b].budget = budgets[b];
        runs[b].session = std::make_unique<PmSession>(pm, whole_frame_options(), options);
        runs[b].session->settle(camera_at(0));
    }
    for (int k = 1; k <= frames; ++k)
        for (WholeRun& r : runs) {
            PmSession& session = *r.session;
            const double c0 = thread_cpu_seconds(), w0 = wall_seconds(), p0 = process_cpu_seconds();
            const View& v = session.render(camera_at(k), 1.0 / 25.0);
            r.cpu.push_back((thread_cpu_seconds() - c0) * 1e3);
            r.wall.push_back((wall_seconds() - w0) * 1e3);
            r.all_cpu.push_back((process_cpu_seconds() - p0) * 1e3);
            r.index_ms.push_back(session.seconds().ray_index * 1e3);
            r.blocks += session.ray_index().blocks;
            r.rebuilt += session.ray_index().rebuilt;
            r.refitted += session.ray_index().refitted;
            const PmFrameSeconds& s = session.seconds();
            // (the view's index and rest: its CPU time less the drawing's wall features and visibility)
            const double parts[11] = {s.adapt,      s.mesh,       s.topology,   s.pierced,
                                      s.curvature,  s.smoothing,  s.session,    s.features, s.visibility,
                                      std::max(0.0, s.view - s.features - s.visibility), s.total};
            for (int i = 0; i < 11; ++i) r.stage[i].push_back(parts[i] * 1e3);
            r.moving += session.moving_search().moving_faces;
            r.pierced += session.adapted().self_intersections().flagged;
            r.triangles += session.stats().triangles;
            r.ray_tests += v.drawing.stats.ray_tests;
            r.inconsistent += v.drawing.stats.clusters_inconsistent;
            r.vertices += session.adapted().topology().vertex_count();
            r.recomputed += session.curvature().recomputed_vertices();
            if (per_frame)
                std::fprintf(stderr, "whole %s frame %d budget %s: %.2f ms, adapt %.3f ms, %zu triangles, %zu moving faces\n",
                             path.c_str(), k, budget_name(r.budget).c_str(), r.cpu.back(), parts[0] * 1e3,
                             session.stats().triangles, session.moving_search().moving_faces);
        }
    for (const WholeRun& r : runs) {
        std::printf("| %s | pm, budget %s | %.0f | %.1f | %.1f |", path_name, budget_name(r.budget).c_str(),
                    double(r.triangles) / frames, median(r.cpu), *std::max_element(r.cpu.begin(), r.cpu.end()));
        for (int i = 0; i < 11; ++i) std::printf(" %.1f |", median(r.stage[i]));
        std::printf(" %.0f | %.0f | %.2f | %.0f | %.0f | %.1f | %zu | %.1f | %.1f | %.2f | %.0f / %.0f / %.0f |\n",
                    double(r.ray_tests) / frames, double(r.inconsistent) / frames,
                    double(r.recomputed) / double(std::max<std::size_t>(1, r.vertices)), double(r.moving) / frames,
                    double(r.pierced) / frames, *std::max_element(r.stage[0].begin(), r.stage[0].end()),
                    r.session->stats().triangles, median(r.wall), median(r.all_cpu), median(r.index_ms),
                    double(r.rebuilt) / frames, double(r.refitted) / frames, double(r.blocks) / frames);
    }
    std::fflush(stdout);
    if (!levels) return;
    MultiscaleSession ms(model, *levels, whole_frame_options(), MultiscaleViewOptions{.target_px = px});
    std::vector<double> cpu, wall, all_cpu;
    std::size_t ray_tests = 0, inconsistent = 0;
    for (int k = 1; k <= frames; ++k) {
        const double c0 = thread_cpu_seconds(), w0 = wall_seconds(), p0 = process_cpu_seconds();
        const View& v = ms.render(camera_at(k));
        cpu.push_back((thread_cpu_seconds() - c0) * 1e3);
        wall.push_back((wall_seconds() - w0) * 1e3);
        all_cpu.push_back((process_cpu_seconds() - p0) * 1e3);
        ray_tests += v.drawing.stats.ray_tests;
        inconsistent += v.drawing.stats.clusters_inconsistent;
    }
    std::printf("| %s | multiscale | %zu | %.1f | %.1f |%s %.0f |", path_name,
                t.faces.size(), median(cpu), *std::max_element(cpu.begin(), cpu.end()),
                " - | - | - | - | - | - | - | - | - | - | - |", double(ray_tests) / frames);
    std::printf(" %.0f |", double(inconsistent) / frames);
    std::printf(" - | - | - | - | - | %.1f | %.1f | - | - |\n", median(wall), median(all_cpu));
    std::fflush(stdout);
}

}  // namespace

const char* const usage =
    "usage: pm_frames [MESH[@N]] [PX] [--no-multiscale] [--path=dolly|orbit|dolly-in] [--geomorphs=on|off]\n"
    "                 [--whole[=FRAMES]] [--budget=N|lag|lag:BASE:FRAMES:MOST[,...]] [--per-frame]\n"
    "  (defaults armadillo 3, both paths, both with and without geomorphs)\n"
    "  --budget     a front (or with --whole a session) per budget, their frames interleaved: N a fixed\n"
    "               budget a frame (0: none), lag the lag-following rule, lag:BASE:FRAMES:MOST another\n"
    "               such rule. Default: none for the front alone; with --whole the sessions' default,\n"
    "               the lag-following rule (as the window and inkline bench run it)\n"
    "  --whole      the whole pm frame (PmSession) by stage, FRAMES frames a path (default 40)\n"
    "  --per-frame  one line a frame on stderr\n";

int main(int argc, char** argv) {
    std::string name = "armadillo";
    double px = 3.0;
    bool multiscale = true;
    std::string only_path;  // "dolly" or "orbit": that path alone (--whole: a list, e.g. dolly,orbit)
    int whole = 0;          // --whole[=FRAMES]: the whole frame, FRAMES frames a path
    std::string only_geomorphs;  // "on" or "off": those runs alone
    std::vector<FrontBudget> budgets;  // --budget=N[,N...]: a run each (0: none); default below
    bool per_frame = false;
    int positional = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h") {
            std::fputs(usage, stdout);
            return 0;
        } else if (a == "--no-multiscale")
            multiscale = false;
        else if (a == "--whole")
            whole = 40;
        else if (a.rfind("--whole=", 0) == 0)
            whole = std::max(1, std::atoi(a.c_str() + 8));
        else if (a.rfind("--path=", 0) == 0)
            only_path = a.substr(7);
        else if (a.rfind("--geomorphs=", 0) == 0)
            only_geomorphs = a.substr(12);
        else if (a.rfind("--budget=", 0) == 0) {
            budgets.clear();
            for (const std::string& n : split_commas(a.substr(9)))
                budgets.push_back(parse_budget(n));
        }
        else if (a == "--per-frame")
            per_frame = true;
        else if (positional++ == 0)
            name = a;
        else
            px = std::atof(a.c_str());
    }
    // (the front alone: unbudgeted, its pinned reference; the whole frame: as the sessions run it)
    if (budgets.empty()) budgets.push_back(whole > 0 ? PmViewOptions::default_budget() : FrontBudget::none());
    const Model* model = bench_model_for(name, "pm_frames");
    if (!model) return 1;
    const MeshTopology& t = model->topology();
    const double rss0 = status_mib("VmRSS");
    double c0 = thread_cpu_seconds();
    const auto w0 = StageClock::now();
    const ProgressiveMesh pm(t);
    const double build_cpu = thread_cpu_seconds() - c0;
    const double build_wall = seconds_since(w0);
    const double rss_pm = status_mib("VmRSS"), peak_pm = status_mib("VmHWM");
    std::size_t front_bytes = 0;  // (a front as it starts: the whole input active)
    {
        const AdaptiveFront front(pm);
        front_bytes = front.bytes();
    }
    std::printf("### %s, PX = %g (T = %g px^2)\n\n", name.c_str(), px, px * px);
    std::printf("%zu triangles, %zu vertices. pm: hierarchy of %zu collapses built in %.2f s CPU (%.1f s wall); "
                "hierarchy %.2f MiB (%.1f B/vertex), front with the whole input active %.1f MiB (%.1f B/vertex; at the "
                "paths' views: the table), the input read from the model; "
                "RSS %.0f -> %.0f MiB, peak %.0f MiB\n",
                t.faces.size(), t.positions.size(), pm.collapses(), build_cpu, build_wall,
                pm.hierarchy_bytes() / 1048576.0, double(pm.hierarchy_bytes()) / t.positions.size(),
                front_bytes / 1048576.0, double(front_bytes) / t.positions.size(), rss0, rss_pm, peak_pm);
    std::unique_ptr<MultiscaleLevels> kept_levels;
    if (multiscale) {
        c0 = thread_cpu_seconds();
        kept_levels = std::make_unique<MultiscaleLevels>(build_multiscale_levels(*model));
        const MultiscaleLevels& levels = *kept_levels;
        std::printf("multiscale: %d levels built in %.2f s CPU; stored %.1f MiB (%.1f B/vertex); RSS now %.0f MiB, "
                    "peak %.0f MiB\n",
                    levels.levels, thread_cpu_seconds() - c0, levels.bytes() / 1048576.0,
                    double(levels.bytes()) / t.positions.size(), status_mib("VmRSS"), status_mib("VmHWM"));
    }
    if (whole > 0) {
        std::printf("\nWhole frame (thread CPU ms; stages: median thread CPU ms, the view split by its wall-clock features and visibility):\n\n"
                    "| path | method | triangles (mean) | frame ms median | frame ms most | adapt | mesh | topology | "
                    "self-intersections | "
                    "curvature | smoothing | session | finder + surface lines | visibility | ray index + rest | "
                    "stages total | ray tests a frame | inconsistent clusters a frame | curvature recomputed (share of vertices) | "
                    "faces moved by geomorphs a frame | self-intersecting faces a frame | adapt ms most | triangles at the end | "
                    "frame wall ms median | frame all-threads CPU ms median | ray index kept across frames: update ms | "
                    "blocks rebuilt / refitted / of a frame |\n"
                    "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for (const std::string path : {"dolly", "orbit", "dolly-in"})
            if (only_path.empty() || std::ranges::count(split_commas(only_path), path) > 0)
                run_whole(*model, pm, kept_levels.get(), px, path, whole, budgets, per_frame);
        return 0;
    }
    DetailCriterion c;
    c.target_area_px = px * px;
    std::printf("\n| path | geomorphs | budget a frame | converge first view ms | triangles first -> last | splits + collapses a frame "
                "(mean, most) | ms a frame median | ms a frame most | largest geomorph move px a frame | "
                "frames deferring (longest run) | catch-up frames at the last view | last mesh | "
                "front B/vertex first -> last (most) |\n"
                "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const bool dolly : {true, false})
        for (const bool geomorphs : {false, true}) {
            if (!only_path.empty() && only_path != (dolly ? "dolly" : "orbit")) continue;
            if (!only_geomorphs.empty() && only_geomorphs != (geomorphs ? "on" : "off")) continue;
            const std::vector<PathResult> results = run_path(pm, t, c, dolly, geomorphs, budgets, per_frame);
            for (std::size_t b = 0; b < budgets.size(); ++b) {
                const PathResult& r = results[b];
                const std::string budget_text = budget_name(budgets[b]);
                const double n = double(t.positions.size());
                std::printf("| %s | %s | %s | %.0f | %zu -> %zu | %.0f, %zu | %.2f | %.2f | %.2f | %zu (%zu) | %zu | %016llx | "
                            "%.1f -> %.1f (%.1f) |\n",
                            dolly ? "dolly 1x -> 4x, 1 %/frame" : "orbit 1 deg/frame", geomorphs ? "0.5 s" : "off",
                            budget_text.c_str(), r.converge_ms, r.tri_first, r.tri_last,
                            double(r.splits + r.collapses) / r.frames, r.most_ops, median(r.ms), r.most_ms,
                            r.largest_move_px, r.deferring_frames, r.longest_deferring, r.catch_up_frames,
                            static_cast<unsigned long long>(r.last_mesh_hash), double(r.bytes_first) / n,
                            double(r.bytes_last) / n, double(r.bytes_most) / n);
            }
            std::fflush(stdout);
        }
    std::printf("\nRSS after the paths %.0f MiB, peak %.0f MiB\n", status_mib("VmRSS"), status_mib("VmHWM"));
    return 0;
}
