#include "core/clock.hpp"
#include "app/bench_detail.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <unordered_set>
#include <vector>

#include <glm/geometric.hpp>

#include "app/progress.hpp"
#include "detail/multiscale.hpp"
#include "detail/progressive_mesh_session.hpp"
#include "output/writers.hpp"

namespace inkline {
namespace {

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// Visible lines sampled every pixel (points in image space).
std::vector<glm::dvec2> visible_samples(const Drawing& d) {
    std::vector<glm::dvec2> out;
    for (const Piece& p : d.pieces) {
        if (p.qi != 0) continue;
        for (std::size_t i = 1; i < p.points.size(); ++i) {
            const glm::dvec2 a = p.points[i - 1], b = p.points[i];
            const int n = std::max(1, int(std::ceil(glm::length(b - a))));
            for (int k = 0; k < n; ++k) out.push_back(a + (b - a) * (double(k) / n));
        }
    }
    return out;
}

// Pixels of `a`'s lines farther than 1 px from every sample of `b` (a 1-px grid of b's samples).
double unmatched_px(const std::vector<glm::dvec2>& a, const std::vector<glm::dvec2>& b) {
    std::unordered_set<long long> cells;
    const auto key = [](long long x, long long y) { return (x << 32) ^ (y & 0xffffffffLL); };
    for (const glm::dvec2& p : b) cells.insert(key((long long)std::floor(p.x), (long long)std::floor(p.y)));
    double n = 0.0;
    for (const glm::dvec2& p : a) {
        const long long x = (long long)std::floor(p.x), y = (long long)std::floor(p.y);
        bool near = false;
        for (long long dx = -1; dx <= 1 && !near; ++dx)
            for (long long dy = -1; dy <= 1 && !near; ++dy) near = cells.count(key(x + dx, y + dy)) != 0;
        n += near ? 0.0 : 1.0;
    }
    return n;
}

struct MethodRow {
    std::string method;
    double build_s = 0.0, stored_mib = 0.0;
    std::vector<double> frame_ms, adapt_ms;
    double triangles = 0.0, operations = 0.0, largest_move_px = 0.0;
    std::size_t tri_first = 0, tri_last = 0;
    double density_first = 0.0, density_last = 0.0;
    double changed_px = 0.0, visible_px = 0.0;  // coherence, summed over consecutive pairs
};

// Visible length over the image area of the model's bounding sphere (issue 43's measure).
double density(const Drawing& d, const MeshTopology& mesh, const Camera& cam) {
    double length = 0.0;
    for (const Piece& p : d.pieces)
        if (p.qi == 0)
            for (std::size_t i = 1; i < p.points.size(); ++i) length += glm::length(p.points[i] - p.points[i - 1]);
    const double r = mesh.bounds.half_diagonal() * cam.focal() / glm::length(cam.eye() - mesh.bounds.center());
    return length / (M_PI * r * r);
}

// One frame's bookkeeping, the same for both methods.
void record(MethodRow& row, const Drawing& d, const MeshTopology& mesh, const Camera& cam, int frame, int frames,
            std::vector<glm::dvec2>& last_samples) {
    const double dens = density(d, mesh, cam);
    if (frame == 0) row.density_first = dens;
    if (frame == frames - 1) row.density_last = dens;
    std::vector<glm::dvec2> samples = visible_samples(d);
    if (frame > 0) {
        row.changed_px += unmatched_px(samples, last_samples) + unmatched_px(last_samples, samples);
        row.visible_px += double(samples.size() + last_samples.size());
    }
    last_samples = std::move(samples);
}

MethodRow run_multiscale(const Model& model, const ViewOptions& base, const DetailBenchArgs& a) {
    MethodRow row;
    row.method = "multiscale";
    MultiscaleOptions options = a.detail->levels_options();
    const std::unique_ptr<ProgressLine> line =
        ProgressLine::on_stderr("bench: smoothed levels", std::size_t(options.build_steps()), "steps");
    options.progress = [&line](int done, int) { line->set_done(std::size_t(done)); };
    const double t0 = thread_cpu_seconds();
    const MultiscaleLevels levels = build_multiscale_levels(model, options);
    row.build_s = thread_cpu_seconds() - t0;
    line->finish();
    row.stored_mib = levels.bytes() / 1048576.0;
    MultiscaleSession session(model, levels, base,
                              MultiscaleViewOptions{.target_px = a.detail->target_px,
                                                    .depth_exponent = a.detail->depth_exponent.value_or(0.0)});
    std::vector<glm::dvec2> last;
    for (int i = 0; i < a.frames; ++i) {
        const Camera cam = a.camera(i);
        const double f0 = thread_cpu_seconds();
        View& v = session.render(cam);
        row.frame_ms.push_back((thread_cpu_seconds() - f0) * 1e3);
        row.adapt_ms.push_back(session.seconds_blend() * 1e3);
        row.triangles += double(model.topology().faces.size());
        record(row, v.drawing, model.topology(), cam, i, a.frames, last);
    }
    row.tri_first = row.tri_last = model.topology().faces.size();
    return row;
}

MethodRow run_pm(const Model& model, const ViewOptions& base, const DetailBenchArgs& a) {
    MethodRow row;
    row.method = "pm";
    const std::size_t most = ProgressiveMesh::most_collapses(model.topology().vertex_count());
    const std::unique_ptr<ProgressLine> line = ProgressLine::on_stderr("bench: pm hierarchy", most, "collapses");
    const double t0 = thread_cpu_seconds();
    const ProgressiveMesh pm(model.topology(), [&line](std::size_t done, std::size_t) { line->set_done(done); });
    row.build_s = thread_cpu_seconds() - t0;
    line->finish();
    PmSession session(pm, base, PmViewOptions::for_path(model, a.detail->target_px));
    session.settle(a.camera(0));  // converged at the first view before the path, as a window opens
    std::vector<glm::dvec2> last;
    const double frame_s = 1.0 / 25.0;
    for (int i = 0; i < a.frames; ++i) {
        const Camera cam = a.camera(i);
        const double f0 = thread_cpu_seconds();
        View& v = session.render(cam, frame_s);
        row.frame_ms.push_back((thread_cpu_seconds() - f0) * 1e3);
        const FrontStats& s = session.stats();
        row.adapt_ms.push_back(s.seconds * 1e3);
        row.triangles += double(s.triangles);
        if (i > 0) row.operations += double(s.splits + s.collapses);
        row.largest_move_px = std::max(row.largest_move_px, s.largest_move_px);
        if (i == 0) row.tri_first = s.triangles;
        row.tri_last = s.triangles;
        record(row, v.drawing, model.topology(), cam, i, a.frames, last);
    }
    row.stored_mib = (pm.hierarchy_bytes() + session.front().bytes()) / 1048576.0;
    return row;
}

}  // namespace

int run_detail_bench(const Model& model, const ViewOptions& base, const DetailBenchArgs& a) {
    std::vector<MethodRow> rows;
    if (a.both || a.detail->method == "multiscale") rows.push_back(run_multiscale(model, base, a));
    if (a.both || a.detail->method == "pm") rows.push_back(run_pm(model, base, a));
    const double n = double(a.frames);
    std::string md = "### " + a.name + " (" + std::to_string(model.topology().faces.size()) + " triangles, " +
                     a.path_note + ", " + std::to_string(a.frames) + " frames, --detail=" +
                     fmt("%g", a.detail->target_px) + ")\n\n"
                     "| method | build s | stored MiB | triangles kept (first -> last) | splits + collapses a frame | "
                     "adapt ms a frame (median) | frame ms (median) | line density first -> last | "
                     "changed lines a frame (share of visible) | largest geomorph move px a frame |\n"
                     "|---|---:|---:|---|---:|---:|---:|---|---:|---:|\n";
    for (const MethodRow& r : rows)
        md += "| " + r.method + " | " + fmt("%.2f", r.build_s) + " | " + fmt("%.1f", r.stored_mib) + " | " +
              fmt("%.0f", double(r.tri_first)) + " -> " + fmt("%.0f", double(r.tri_last)) + " | " +
              (r.method == "pm" ? fmt("%.0f", r.operations / std::max(1.0, n - 1)) : std::string("-")) + " | " +
              fmt("%.2f", median(r.adapt_ms)) + " | " + fmt("%.1f", median(r.frame_ms)) + " | " +
              fmt("%.4f", r.density_first) + " -> " + fmt("%.4f", r.density_last) + " | " +
              fmt("%.3f", r.visible_px > 0.0 ? r.changed_px / r.visible_px : 0.0) + " | " +
              (r.method == "pm" ? fmt("%.2f", r.largest_move_px) : std::string("-")) + " |\n";
    std::fputs(md.c_str(), stdout);
    if (!a.markdown.empty()) write_text_file(a.markdown, md);
    return 0;
}

}  // namespace inkline
