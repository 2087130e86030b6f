// The tone pass (src/tone/) stage by stage: shading, blur, ridge search, tracing, on the framed
// camera of a sample mesh, at given sizes and thread counts; medians and minima of wall time over
// repeated passes into the same ToneResult (the window's steady state: storage reused).
// Usage: bench_tone [MESH ...]   (default armadillo); prints a markdown table.
//        bench_tone --agreement [MESH ...]   (default bunny00 armadillo): the share of tone-dark
//        length within 3 px of visible suggestive contours (and back), and how far the lines move
//        when the light turns by 1 degree about the camera's up axis.
#include <algorithm>
#include <cmath>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <unordered_map>

#include "core/clock.hpp"
#include "pipeline.hpp"
#include "tone/tone.hpp"

using namespace inkline;

namespace {
double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}
// Points along polylines, one per `step` px, bucketed in a grid of `cell` px.
struct PointGrid {
    double cell;
    std::unordered_map<long long, std::vector<glm::dvec2>> cells;
    explicit PointGrid(double c) : cell(c) {}
    long long key(long long x, long long y) const { return x * 1000003LL + y; }
    void add(const glm::dvec2& p) { cells[key((long long)std::floor(p.x / cell), (long long)std::floor(p.y / cell))].push_back(p); }
    double nearest(const glm::dvec2& p) const {
        double best = 1e300;
        const long long cx = (long long)std::floor(p.x / cell), cy = (long long)std::floor(p.y / cell);
        for (long long dy = -1; dy <= 1; ++dy)
            for (long long dx = -1; dx <= 1; ++dx) {
                const auto it = cells.find(key(cx + dx, cy + dy));
                if (it == cells.end()) continue;
                for (const glm::dvec2& q : it->second) best = std::min(best, glm::length(p - q));
            }
        return best;
    }
};

// Calls fn(point, length it stands for) along the pieces, a point every `step` px.
template <class Fn>
void along(const std::vector<const Piece*>& pieces, double step, Fn&& fn) {
    for (const Piece* p : pieces)
        for (std::size_t i = 1; i < p->points.size(); ++i) {
            const glm::dvec2 a = p->points[i - 1], b = p->points[i];
            const double l = glm::length(b - a);
            const int n = std::max(1, int(std::ceil(l / step)));
            for (int k = 0; k < n; ++k) fn(a + (k + 0.5) / n * (b - a), l / n);
        }
}

// Share of a's length within `radius` px of b; and the mean distance of a's points to b.
std::pair<double, double> near_share(const std::vector<const Piece*>& a, const std::vector<const Piece*>& b,
                                     double radius) {
    PointGrid grid(std::max(radius, 4.0));
    along(b, 0.5, [&](const glm::dvec2& p, double) { grid.add(p); });
    double near = 0.0, total = 0.0, sum = 0.0, n = 0.0;
    along(a, 1.0, [&](const glm::dvec2& p, double l) {
        const double d = grid.nearest(p);
        total += l;
        if (d <= radius) near += l;
        sum += std::min(d, grid.cell);  // (beyond the grid's reach: counted as the cell size)
        n += 1.0;
    });
    return {total > 0 ? near / total : 0.0, n > 0 ? sum / n : 0.0};
}

std::vector<const Piece*> of_kind(const std::vector<Piece>& pieces, LineKind kind) {
    std::vector<const Piece*> out;
    for (const Piece& p : pieces)
        if (p.kind == kind && p.qi == 0) out.push_back(&p);
    return out;
}

double length(const std::vector<const Piece*>& pieces) {
    double l = 0.0;
    along(pieces, 1.0, [&](const glm::dvec2&, double s) { l += s; });
    return l;
}

int agreement(std::vector<std::string> meshes) {
    if (meshes.empty()) meshes = {"bunny00", "armadillo"};
    std::printf("| mesh | tone-dark px | suggestive px | tone-dark within 3 px of suggestive | suggestive within 3 px of "
                "tone-dark | light turned 1 deg: tone-dark px | moved points within 1 px | mean distance (px) |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    for (const std::string& name : meshes) {
        const Model model = Model::load(std::string(INKLINE_DATA_DIR) + "/meshes/" + name + ".off");
        Camera cam = Camera::framing(model.topology().bounds, 1024, 1024);
        cam.set_near(default_near(model.topology()));
        ViewOptions vo;
        vo.surface.suggestive = true;
        const View view = render_view(model, cam, vo);
        const tone::ToneMesh normals = tone::prepare_tone_mesh(model.topology());
        tone::ToneOptions o;
        tone::ToneResult r0, r1;
        tone::render_tone(model.topology(), normals, cam, o, true, false, r0);
        const glm::dvec3 l0 = tone::default_light(cam);
        const glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), glm::radians(1.0), cam.upward());
        o.lights = {glm::dvec3(turn * glm::dvec4(l0, 0.0))};
        tone::render_tone(model.topology(), normals, cam, o, true, false, r1);
        const auto dark0 = of_kind(r0.pieces, LineKind::ToneDark), dark1 = of_kind(r1.pieces, LineKind::ToneDark);
        const auto sugg = of_kind(view.drawing.pieces, LineKind::Suggestive);
        const auto [tone_near, unused0] = near_share(dark0, sugg, 3.0);
        const auto [sugg_near, unused1] = near_share(sugg, dark0, 3.0);
        const auto [moved_near, moved_mean] = near_share(dark1, dark0, 1.0);
        std::printf("| %s | %.0f | %.0f | %.1f %% | %.1f %% | %.0f | %.1f %% | %.2f |\n", name.c_str(), length(dark0),
                    length(sugg), 100 * tone_near, 100 * sugg_near, length(dark1), 100 * moved_near, moved_mean);
        std::fflush(stdout);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> meshes;
    for (int i = 1; i < argc; ++i) meshes.push_back(argv[i]);
    if (!meshes.empty() && meshes[0] == "--agreement") return agreement({meshes.begin() + 1, meshes.end()});
    if (meshes.empty()) meshes = {"armadillo"};
    constexpr int kRuns = 15;
    std::printf("| mesh | size | threads | shade | blur | ridges | trace | total (median) | total (min) | CPU: shade, blur, ridges, trace = total | dark, highlight lines |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const std::string& name : meshes) {
        const Model model = Model::load(std::string(INKLINE_DATA_DIR) + "/meshes/" + name + ".off");
        const tone::ToneMesh normals = tone::prepare_tone_mesh(model.topology());
        for (auto [w, h] : {std::pair{800, 600}, std::pair{1024, 1024}})
            for (int threads : {1, 2}) {
                Camera cam = Camera::framing(model.topology().bounds, w, h);
                cam.set_near(default_near(model.topology()));
                tone::ToneOptions o;
                o.threads = threads;
                tone::ToneResult r;
                tone::render_tone(model.topology(), normals, cam, o, true, true, r);  // warm-up
                std::vector<double> shade, blur, ridges, trace, total;
                std::vector<double> cpu[4];  // one thread: the stages' CPU time (load-independent)
                for (int k = 0; k < kRuns && threads == 1; ++k) {
                    double c = inkline::thread_cpu_seconds();
                    const auto lap = [&](int stage) {
                        const double now = inkline::thread_cpu_seconds();
                        cpu[stage].push_back(now - c);
                        c = now;
                    };
                    tone::shade(model.topology(), normals, cam, o, r.shaded);
                    lap(0);
                    tone::gaussian_blur(r.shaded.tone, o.width, r.tone_blurred, 1, &r.blur_scratch);
                    tone::gaussian_blur(r.shaded.specular, o.width, r.specular_blurred, 1, &r.blur_scratch);
                    lap(1);
                    tone::detect_ridges_both(r.tone_blurred, r.tone_blurred, &r.dark, &r.highlight, o);
                    tone::detect_ridges(r.specular_blurred, r.specular_blurred, tone::Polarity::Light, o.highlight_lower,
                                        o.highlight_upper, o, r.specular);
                    tone::merge_max(r.highlight, r.specular);
                    lap(2);
                    const auto d = tone::trace_lines(r.dark, LineKind::ToneDark, o);
                    const auto h = tone::trace_lines(r.highlight, LineKind::ToneHighlight, o);
                    lap(3);
                }
                std::string cpu_cell = "-";
                if (threads == 1) {
                    char b[96];
                    std::snprintf(b, sizeof b, "%.1f, %.1f, %.1f, %.1f = %.1f", 1e3 * median(cpu[0]), 1e3 * median(cpu[1]),
                                  1e3 * median(cpu[2]), 1e3 * median(cpu[3]),
                                  1e3 * (median(cpu[0]) + median(cpu[1]) + median(cpu[2]) + median(cpu[3])));
                    cpu_cell = b;
                }
                for (int k = 0; k < kRuns; ++k) {
                    tone::render_tone(model.topology(), normals, cam, o, true, true, r);
                    shade.push_back(r.seconds.shade);
                    blur.push_back(r.seconds.blur);
                    ridges.push_back(r.seconds.ridges);
                    trace.push_back(r.seconds.trace);
                    total.push_back(r.seconds.total());
                }
                std::size_t dark = 0;
                for (const Piece& p : r.pieces) dark += p.kind == LineKind::ToneDark;
                std::printf("| %s | %dx%d | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %s | %zu, %zu |\n", name.c_str(), w, h,
                            threads, 1e3 * median(shade), 1e3 * median(blur), 1e3 * median(ridges), 1e3 * median(trace),
                            1e3 * median(total), 1e3 * *std::min_element(total.begin(), total.end()),
                            cpu_cell.c_str(), dark,
                            r.pieces.size() - dark);
                std::fflush(stdout);
            }
    }
    return 0;
}
