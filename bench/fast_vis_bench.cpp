// The fast visibility (--visibility=fast) against the exact method (appel), issue 46 item 1: per
// mesh, the frame's time (features + visibility, one ViewSession per method, storage reused, as
// the window and the bench command run it) and the error: visible length of the fast drawing
// farther than 1 px from the exact drawing's visible lines (extra) and the reverse (missing).
// Views: the bench's orbit (bench_models.hpp: 20 degrees above the equator, every 360/N degrees),
// 1024 x 1024. Each view's time is the median of its repeats; a mesh's is the mean over views.
// Usage: fast_vis_bench [--meshes=a,b,...] [--buffers=256,512,...] [--views=N] [--repeats=K]
//                       [--svg=PATH] [--exact-repeats=K]
// (--svg: the accuracy/time curve, the buffer's size as the knob; --exact-repeats: the exact frames'
// repeats when they differ from --repeats, e.g. 1 to profile the fast frames alone)
// Prints a markdown table, one row per (mesh, buffer).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_models.hpp"
#include "pipeline.hpp"
#include "visibility/line_difference.hpp"

namespace {

using namespace inkline;

struct Row {
    std::string mesh;
    int buffer = 0;
    double exact_ms = 0, fast_ms = 0, exact_wall = 0, fast_wall = 0, missing = 0, extra = 0, reference = 0;
    std::size_t ray_tests = 0, ambiguous = 0, samples = 0;
    // The last repeat's stage times (the drawing's stats), mean over the views, ms.
    double exact_features = 0, exact_visibility = 0, fast_features = 0, fast_visibility = 0;
    double share() const { return reference > 0 ? (missing + extra) / reference : 0.0; }
};

struct Times {
    double cpu_ms = 0, wall_ms = 0;
};

// Median CPU and wall times of `repeats` renders of `cam` by `session`, ms; the last view stays in
// it. CPU time is the comparison: on a shared, oversubscribed core a frame longer than the
// scheduler's slice waits for the other tasks' slices, and its wall time jumps 5-30x while its
// CPU time does not (that, not the code, was the fast frame's "unexplained" jumps).
Times time_view(ViewSession& session, const Camera& cam, int repeats) {
    std::vector<double> cpu, wall;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        const double c0 = process_cpu_ms();
        session.render(cam);
        cpu.push_back(process_cpu_ms() - c0);
        wall.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(cpu.begin(), cpu.end()), std::sort(wall.begin(), wall.end());
    return {cpu[cpu.size() / 2], wall[wall.size() / 2]};
}

FastVisibilityOptions g_fast;  // --margin, --cusp, --short-run, --exact-lone-cusps

int g_exact_repeats = 0;  // --exact-repeats (0: as --repeats), e.g. 1 to profile the fast frames alone

std::vector<Row> bench_mesh(const std::string& name, const std::vector<int>& buffers, int views, int repeats) {
    const Model* m = bench_model_for(name, "fast_vis_bench");
    if (!m) return {};
    m->rays();  // once per model, outside the frames (as bench_frame)
    m->self_intersecting_faces();
    const MeshTopology& t = m->topology();
    std::vector<Camera> cams;
    for (int k = 0; k < views; ++k)
        cams.push_back(Camera::perspective(orbit_eye(t, 360.0 * k / views), t.bounds.center(), {0, 1, 0}, 30, 1024, 1024));
    ViewOptions exact;
    exact.exact_hidden = false;  // visible lines, as render without --hidden
    ViewSession es(*m, exact);
    std::vector<Drawing> reference;
    Times exact_t;
    double exact_features = 0, exact_visibility = 0;
    for (const Camera& c : cams) {
        const Times t = time_view(es, c, g_exact_repeats > 0 ? g_exact_repeats : repeats);
        exact_t.cpu_ms += t.cpu_ms / views, exact_t.wall_ms += t.wall_ms / views;
        reference.push_back(es.render(c).drawing);
        exact_features += 1e3 * reference.back().stats.seconds_features / views;
        exact_visibility += 1e3 * reference.back().stats.seconds_visibility / views;
    }
    std::vector<Row> rows;
    for (int b : buffers) {
        ViewOptions fast = exact;
        fast.visibility = VisibilityMethod::Fast;
        fast.fast = g_fast;
        fast.fast.buffer_px = b;
        ViewSession fs(*m, fast);
        Row r{name, b, exact_t.cpu_ms, 0.0, exact_t.wall_ms};
        r.exact_features = exact_features, r.exact_visibility = exact_visibility;
        for (std::size_t k = 0; k < cams.size(); ++k) {
            const Times t = time_view(fs, cams[k], repeats);
            r.fast_ms += t.cpu_ms / views, r.fast_wall += t.wall_ms / views;
            const View& v = fs.render(cams[k]);
            const LineDifference d = visible_difference(reference[k], v.drawing);
            r.missing += d.missing_px, r.extra += d.extra_px, r.reference += d.reference_px;
            r.ray_tests += v.drawing.stats.ray_tests;
            r.fast_features += 1e3 * v.drawing.stats.seconds_features / views;
            r.fast_visibility += 1e3 * v.drawing.stats.seconds_visibility / views;
        }
        rows.push_back(r);
    }
    return rows;
}

// The accuracy/time curve: x the fast frame's time as a share of the exact one's (up to 2), y the share of
// visible length that differs (log scale), one polyline per mesh, points labelled by buffer size.
std::string svg_plot(const std::vector<Row>& rows) {
    const double W = 720, H = 480, L = 70, R = 170, T = 30, B = 50;
    const double ymin = -5, ymax = -1;  // log10 of the share: 0.001 % .. 10 %
    auto X = [&](double ratio) { return L + std::clamp(ratio, 0.0, 2.0) / 2.0 * (W - L - R); };  // (clamped at 2)
    auto Y = [&](double share) {
        const double l = std::log10(std::max(share, 1e-5));
        return T + (ymax - std::clamp(l, ymin, ymax)) / (ymax - ymin) * (H - T - B);
    };
    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
      << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    for (int e = -5; e <= -1; ++e) {
        const double y = Y(std::pow(10.0, e));
        o << "<line x1=\"" << L << "\" x2=\"" << W - R << "\" y1=\"" << y << "\" y2=\"" << y
          << "\" stroke=\"#ddd\"/><text x=\"" << L - 6 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">"
          << std::pow(10.0, e + 2) << " %</text>\n";
    }
    const double y05 = Y(0.005);
    o << "<line x1=\"" << L << "\" x2=\"" << W - R << "\" y1=\"" << y05 << "\" y2=\"" << y05
      << "\" stroke=\"#c00\" stroke-dasharray=\"4 3\"/><text x=\"" << W - R + 4 << "\" y=\"" << y05 + 4
      << "\" fill=\"#c00\">target 0.5 %</text>\n";
    for (int k = 0; k <= 10; ++k) {
        const double x = X(k / 5.0);
        o << "<line x1=\"" << x << "\" x2=\"" << x << "\" y1=\"" << T << "\" y2=\"" << H - B
          << "\" stroke=\"#eee\"/><text x=\"" << x << "\" y=\"" << H - B + 14 << "\" text-anchor=\"middle\">" << k / 5.0
          << "</text>\n";
    }
    o << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 12
      << "\" text-anchor=\"middle\">fast frame time / exact frame time (one core; 2 or more drawn at 2)</text>\n";
    o << "<text x=\"14\" y=\"" << (T + H - B) / 2 << "\" transform=\"rotate(-90 14 " << (T + H - B) / 2
      << ")\" text-anchor=\"middle\">visible length differing (missing + extra, 1 px)</text>\n";
    const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};
    std::vector<std::string> meshes;
    for (const Row& r : rows)
        if (std::find(meshes.begin(), meshes.end(), r.mesh) == meshes.end()) meshes.push_back(r.mesh);
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const char* c = colours[i % 8];
        std::ostringstream pts;
        for (const Row& r : rows)
            if (r.mesh == meshes[i]) {
                const double x = X(r.fast_ms / r.exact_ms), y = Y(r.share());
                pts << x << "," << y << " ";
                o << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"3\" fill=\"" << c << "\"/><text x=\"" << x + 4
                  << "\" y=\"" << y - 4 << "\" fill=\"" << c << "\" font-size=\"9\">" << r.buffer << "</text>\n";
            }
        o << "<polyline points=\"" << pts.str() << "\" fill=\"none\" stroke=\"" << c << "\"/>\n";
        o << "<text x=\"" << W - R + 10 << "\" y=\"" << T + 40 + 16 * i << "\" fill=\"" << c << "\">" << meshes[i]
          << "</text>\n";
    }
    o << "<text x=\"" << W - R + 10 << "\" y=\"" << T + 40 + 16 * meshes.size() + 10
      << "\" font-size=\"9\">labels: buffer px (long side)</text>\n</svg>\n";
    return o.str();
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> meshes = {"fandisk", "bunny00", "knot1", "armadillo", "elephant", "ChineseDragon-10kv"};
    std::vector<int> buffers = {512};
    int views = 8, repeats = 5;
    std::string svg;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&](const char* flag) { return a.substr(std::string(flag).size()); };
        if (a.rfind("--meshes=", 0) == 0) meshes = split_commas(value("--meshes="));
        else if (a.rfind("--buffers=", 0) == 0) {
            buffers.clear();
            for (const std::string& b : split_commas(value("--buffers="))) buffers.push_back(std::stoi(b));
        } else if (a.rfind("--views=", 0) == 0) views = std::max(1, std::stoi(value("--views=")));
        else if (a.rfind("--repeats=", 0) == 0) repeats = std::max(1, std::stoi(value("--repeats=")));
        else if (a.rfind("--svg=", 0) == 0) svg = value("--svg=");
        else if (a.rfind("--exact-repeats=", 0) == 0) g_exact_repeats = std::max(1, std::stoi(value("--exact-repeats=")));
        else if (a.rfind("--margin=", 0) == 0) g_fast.margin_px = std::stod(value("--margin="));
        else if (a.rfind("--cusp=", 0) == 0) g_fast.cusp_px = std::stod(value("--cusp="));
        else if (a.rfind("--short-run=", 0) == 0) g_fast.short_run = std::stoul(value("--short-run="));
        else if (a == "--exact-lone-cusps") g_fast.exact_lone_cusps = true;
        else {
            std::fprintf(stderr, "fast_vis_bench: unknown argument %s\n", a.c_str());
            return 2;
        }
    }
    std::printf("| mesh | buffer px | exact ms | fast ms | ratio | missing px | extra px | %% differing | ray tests/view "
                "| wall exact / fast ms |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    std::vector<Row> all;
    for (const std::string& m : meshes)
        for (const Row& r : bench_mesh(m, buffers, views, repeats)) {
            std::printf("| %s | %d | %.3f | %.3f | %.2fx | %.1f | %.1f | %.3f %% | %.0f | %.3f / %.3f |\n", r.mesh.c_str(),
                        r.buffer, r.exact_ms, r.fast_ms, r.exact_ms / r.fast_ms, r.missing, r.extra, 100.0 * r.share(),
                        double(r.ray_tests) / views, r.exact_wall, r.fast_wall);
            std::fprintf(stderr, "%s %d: features %.3f / %.3f ms, visibility %.3f / %.3f ms (exact / fast)\n",
                         r.mesh.c_str(), r.buffer, r.exact_features, r.fast_features, r.exact_visibility,
                         r.fast_visibility);
            std::fflush(stdout);
            all.push_back(r);
        }
    std::printf("\n(%d views of the bench's orbit at 1024 x 1024; ms: the process's CPU time a frame, median of the "
                "repeats, mean over the views; error summed over the views, of %s px visible)\n",
                views, "the exact drawings'");
    if (!svg.empty()) std::ofstream(svg) << svg_plot(all);
    return 0;
}
