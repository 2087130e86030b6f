// `inkline bench`: the speed/accuracy trade of the silhouette finders along a camera path.
// For every setting (exhaustive; randomized at several sample fractions, with and without frame
// coherence) the model is drawn frame by frame along the path; the finder stage (silhouette
// search, cusps, chaining) is timed, and its result is compared with the exhaustive finder's on
// the same frame: recall of silhouette length, and the length of visible line (after visibility,
// every line kind) that is missing or extra, in pixels.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "app/bench_detail.hpp"
#include "app/cli.hpp"
#include "app/flags.hpp"
#include "app/progress.hpp"
#include "core/error.hpp"
#include "model/primitives.hpp"
#include "model/reorder.hpp"
#include "model/subdivide.hpp"
#include "output/writers.hpp"
#include "pipeline.hpp"

namespace inkline {
namespace {

struct BenchArgs {
    std::string model, path = "orbit", csv, markdown, plot;
    int frames = 60, subdivide = 0, threads = hardware_threads();
    std::optional<int> width = 1024, height = 1024;
    bool first_full = false;  // coherence rows: the first view by the exhaustive scan
    double arc = 360.0;  // orbit: degrees covered by the frames
    std::uint64_t seed = 1;
    double crease = 40.0;
    bool strict = false;  // --strict: refuse what tolerant loading repairs
    std::vector<double> fractions{0.0005, 0.002, 0.01, 0.05};
    VisibilityMethod visibility = VisibilityMethod::Appel;
    DetailFlags detail;  // --detail: the detail-control methods instead of the finders (bench_detail.hpp)
    int fast_buffer = 0;  // not given: fast_buffer_px gives the default
};

// The bench's flags; `--fractions` and the camera path are its own, the rest shared (flags.hpp).
FlagTable bench_flags(BenchArgs& a) {
    FlagTable t("bench", "bench MODEL [FLAGS]",
                "Times the silhouette finders (exhaustive; randomized at several sample fractions, with and "
                "without frame coherence) along a camera path, and compares each frame with the exhaustive "
                "finder's: recall of silhouette length and visible line missing or extra, in pixels. Prints a "
                "Markdown table. MODEL: a mesh file, or 'tori:N' (two linked tori of N x N/2 segments each).");
    t.group("Camera path")
        .add({"--path", "orbit|dolly|walk", "the camera's path around the model (default orbit)",
              [&a](const std::string& v) {
                  if (v != "orbit" && v != "dolly" && v != "walk")
                      throw Error("--path", "unknown path '" + v + "' (expected orbit, dolly or walk)");
                  a.path = v;
              }})
        .add(frames_flag(a.frames, "frames along the path (default 60)"))
        .add(arc_flag(a.arc, "orbit: degrees covered by the frames"))
        .add(size_flag(a.width, a.height));
    t.group("Model").add(subdivide_flag(a.subdivide)).add(crease_flag(a.crease)).add(strict_flag(a.strict));
    t.group("Silhouette finders")
        .add({"--fractions", "F,F,...", "randomized finder's shares of the edges, each in (0, 1] "
                                        "(default 0.0005,0.002,0.01,0.05)",
              [&a](const std::string& v) {
                  a.fractions.clear();
                  std::stringstream ss(v);
                  for (std::string f; std::getline(ss, f, ',');) {
                      const double share = parse_number("--fractions", f);
                      if (!(share > 0.0 && share <= 1.0))
                          throw Error("--fractions", "expected shares in (0, 1], got '" + f + "'");
                      a.fractions.push_back(share);
                  }
              }})
        .add(seed_flag(a.seed))
        .add(first_view_flag(a.first_full))
        .add(threads_flag(a.threads, "the machine's hardware threads"));
    t.group("Visibility").add(visibility_flag(a.visibility)).add(fast_buffer_flag(a.fast_buffer));
    t.group("Detail control (with --detail: both methods along the path, or the one --detail-method names)")
        .add(detail_flags(a.detail));
    t.group("Output (the table always goes to stdout)")
        .add(text_flag("--csv", "FILE", a.csv, "the rows as CSV"))
        .add(text_flag("--markdown", "FILE", a.markdown, "the table as Markdown"))
        .add(text_flag("--plot", "FILE.svg", a.plot, "finder time against recall, as an SVG scatter plot"));
    return t;
}

// "tori:N": two linked tori, N x N/2 segments each (the paper's Tables 1 and 2 model).
Model load_model(const BenchArgs& a) {
    if (a.model.rfind("tori:", 0) == 0) {
        const int n = parse_integer("MODEL", a.model.substr(5), 8, 4096);
        const TriangleMesh t = merge_meshes(make_torus({0, 0, 0}, {0, 0, 1}, 1.0, 0.3, n, n / 2),
                                            make_torus({1, 0, 0}, {0, 1, 0}, 1.0, 0.3, n, n / 2));
        return Model(hilbert_ordered(subdivide_loop(t, a.subdivide)), a.crease);
    }
    return load_model_file(a.model, a.strict, a.crease, a.subdivide);
}

// Smooth camera paths around the model's bounding box (R: half diagonal, D: framing distance).
Camera path_camera(const std::string& path, int i, int frames, double arc, const Bounds3& box, int w, int h) {
    const double fov = 30.0, R = box.half_diagonal(), D = R / std::sin(fov * M_PI / 360.0);
    const glm::dvec3 c = box.center();
    const double t = frames > 1 ? double(i) / double(frames - 1) : 0.0;
    if (path == "orbit") {  // `arc` degrees around (arc / frames per frame), 20 degrees above the equator
        const double az = arc * M_PI / 180.0 * double(i) / double(frames), el = 20.0 * M_PI / 180.0;
        const glm::dvec3 dir(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
        return Camera::perspective(c + D * dir, c, {0, 1, 0}, fov, w, h);
    }
    const glm::dvec3 dir = glm::normalize(glm::dvec3(1.0, 0.6, 1.4));
    if (path == "dolly") {  // from 1.5 D in to 0.6 D along the default view direction
        return Camera::perspective(c + (1.5 - 0.9 * t) * D * dir, c, {0, 1, 0}, fov, w, h);
    }
    // walk: a camera passing the model sideways at 0.8 D, looking ahead of itself, slight bob.
    const glm::dvec3 side = glm::normalize(glm::cross(dir, glm::dvec3(0, 1, 0)));
    const glm::dvec3 eye = c + 0.8 * D * dir + (t - 0.5) * 1.6 * R * side + 0.05 * R * std::sin(12.0 * t) * glm::dvec3(0, 1, 0);
    const glm::dvec3 target = c + (t - 0.5) * 0.8 * R * side;
    return Camera::perspective(eye, target, {0, 1, 0}, fov, w, h);
}

struct Interval {
    std::uint32_t edge;
    double s0, s1;
};

std::vector<Interval> visible_intervals(const View& v) {
    std::vector<Interval> out;
    for (std::size_t i = 0; i < v.drawing.pieces.size(); ++i) {
        if (v.drawing.pieces[i].qi != 0) continue;
        for (const EdgeSpan& s : v.spans[i]) out.push_back({s.edge, std::min(s.s0, s.s1), std::max(s.s0, s.s1)});
    }
    std::sort(out.begin(), out.end(), [](const Interval& a, const Interval& b) {
        return a.edge != b.edge ? a.edge < b.edge : a.s0 < b.s0;
    });
    return out;
}

// Pixel length of the symmetric difference of two sets of visible edge intervals.
double wrong_length_px(const MeshTopology& mesh, const Camera& cam, const std::vector<Interval>& a,
                       const std::vector<Interval>& b) {
    double wrong = 0.0;
    std::size_t i = 0, j = 0;
    std::vector<double> cuts;
    while (i < a.size() || j < b.size()) {
        const std::uint32_t e = std::min(i < a.size() ? a[i].edge : UINT32_MAX, j < b.size() ? b[j].edge : UINT32_MAX);
        const std::size_t i0 = i, j0 = j;
        while (i < a.size() && a[i].edge == e) ++i;
        while (j < b.size() && b[j].edge == e) ++j;
        cuts.clear();
        for (std::size_t k = i0; k < i; ++k) cuts.insert(cuts.end(), {a[k].s0, a[k].s1});
        for (std::size_t k = j0; k < j; ++k) cuts.insert(cuts.end(), {b[k].s0, b[k].s1});
        std::sort(cuts.begin(), cuts.end());
        const glm::dvec3 p0 = mesh.positions[mesh.edge_vertex[e][0]], p1 = mesh.positions[mesh.edge_vertex[e][1]];
        auto inside = [](const std::vector<Interval>& v, std::size_t lo, std::size_t hi, double s) {
            for (std::size_t k = lo; k < hi; ++k)
                if (v[k].s0 <= s && s <= v[k].s1) return true;
            return false;
        };
        for (std::size_t k = 1; k < cuts.size(); ++k) {
            if (cuts[k] <= cuts[k - 1]) continue;
            const double m = 0.5 * (cuts[k] + cuts[k - 1]);
            if (inside(a, i0, i, m) == inside(b, j0, j, m)) continue;
            wrong += glm::length(cam.project(p0 + cuts[k] * (p1 - p0)) - cam.project(p0 + cuts[k - 1] * (p1 - p0)));
        }
    }
    return wrong;
}

struct Row {
    std::string finder;
    double fraction = 1.0;
    bool coherence = false;
    double features_s = 0.0, search_s = 0.0, visibility_s = 0.0;
    double silhouette_edges = 0.0, found_length = 0.0, wrong_px = 0.0;
    double band_faces = 0.0, faces_turned = 0.0;  // coherence: per frame, summed
    std::vector<double> search_frames;  // per frame, for the median (robust on a shared machine)
};

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

// bench --detail: silhouettes and suggestive contours (creases off: the lines detail control is
// about), exhaustive finder, along the path.
int run_detail_bench_path(const Model& model, const std::string& name, const BenchArgs& a) {
    ViewOptions base;
    base.visibility = a.visibility;
    base.exact_hidden = false;
    base.surface.suggestive = true;
    base.features.kinds[int(LineKind::Crease)] = false;
    DetailBenchArgs d;
    d.name = name;
    d.path_note = a.path == "orbit" ? "orbit " + fmt("%g", a.arc / a.frames) + " deg/frame" : a.path;
    d.markdown = a.markdown;
    d.detail = &a.detail;
    d.both = !a.detail.method_given;
    d.frames = a.frames;
    const double near = default_near(model.topology());
    d.camera = [&](int i) {
        Camera c = path_camera(a.path, i, a.frames, a.arc, model.topology().bounds, *a.width, *a.height);
        c.set_near(near);
        return c;
    };
    return run_detail_bench(model, base, d);
}

}  // namespace

int run_bench(int argc, char** argv) {
    BenchArgs a;
    if (!bench_flags(a).parse(argc, argv, 2, a.model)) return 0;  // --help
    const Model model = load_model(a);
    const MeshTopology& mesh = model.topology();
    const std::size_t nf = mesh.face_count();
    std::string name = a.model.substr(a.model.find_last_of('/') + 1);
    name = name.substr(0, name.rfind(".") == std::string::npos || name.rfind(".") == 0 ? name.size() : name.rfind("."));
    if (a.subdivide > 0) name += "@" + std::to_string(a.subdivide);
    a.detail.check("bench");
    if (a.detail.target_px > 0.0) return run_detail_bench_path(model, name, a);
    std::vector<Camera> cams;
    for (int i = 0; i < a.frames; ++i) {
        cams.push_back(path_camera(a.path, i, a.frames, a.arc, mesh.bounds, *a.width, *a.height));
        cams.back().set_near(default_near(mesh));
    }
    std::fprintf(stderr, "bench: %s, %zu triangles, %s path, %d frames\n", name.c_str(), nf, a.path.c_str(), a.frames);

    ViewOptions base;
    base.visibility = a.visibility;
    base.exact_hidden = false;
    base.threads = a.threads;  // (the finders' facing pass and scan and every setting's visibility)
    base.fast.buffer_px = fast_buffer_px(a.fast_buffer, a.visibility);

    // The settings, known before the first view so that the progress line counts every view.
    std::vector<FinderOptions> settings;
    settings.push_back({});
    settings.back().threads = a.threads;
    for (bool coherence : {false, true})
        for (double f : a.fractions) {
            FinderOptions o;
            o.threads = a.threads;
            o.kind = FinderKind::Randomized;
            o.fraction = f;
            o.coherence = coherence;
            o.seed = a.seed;
            o.first_full = coherence && a.first_full;
            settings.push_back(o);
        }
    auto progress = ProgressLine::on_stderr("bench", cams.size() * (1 + settings.size()), "views");

    // The reference: the exhaustive finder on every frame.
    std::vector<double> ref_length(cams.size());
    std::vector<std::vector<Interval>> ref_visible(cams.size());
    {
        ViewSession ref(model, base);
        for (std::size_t i = 0; i < cams.size(); ++i) {
            View& v = ref.render(cams[i]);
            ref_length[i] = edges_length(mesh, v.features.silhouette_edges);
            ref_visible[i] = visible_intervals(v);
            progress->advance();
        }
    }
    double ref_total = 0.0;
    for (double l : ref_length) ref_total += l;

    // Every setting has its own session (its own frame coherence), and the settings take turns
    // frame by frame: on a shared machine a burst of load then slows every setting alike, and the
    // ratios between them (the slowdown of exhaustive) are measured under the same conditions.
    // (Run one after another, a burst during one setting's frames alone skewed its ratio.) Each
    // setting's frame follows another setting's visibility stage, as in a pipeline: cold caches.
    std::vector<Row> rows(settings.size());
    std::vector<std::unique_ptr<ViewSession>> sessions;
    for (std::size_t k = 0; k < settings.size(); ++k) {
        const FinderOptions& fo = settings[k];
        ViewOptions opt = base;
        opt.finder = fo;
        sessions.push_back(std::make_unique<ViewSession>(model, opt));
        Row& r = rows[k];
        r.finder = finder_name(fo.kind);
        r.fraction = fo.kind == FinderKind::Exhaustive ? 1.0 : fo.fraction;
        r.coherence = fo.kind == FinderKind::Randomized && fo.coherence;
        r.search_frames.reserve(cams.size());
    }
    for (std::size_t i = 0; i < cams.size(); ++i)
        for (std::size_t k = 0; k < settings.size(); ++k) {
            ViewSession& session = *sessions[k];
            Row& r = rows[k];
            const Features& f = session.find(cams[i]);
            r.features_s += session.seconds_features();
            r.search_s += f.stats.seconds_search;
            r.search_frames.push_back(f.stats.seconds_search);
            r.silhouette_edges += double(f.silhouette_edges.size());
            r.band_faces += double(f.stats.band_faces);
            r.faces_turned += double(f.stats.faces_turned);
            r.found_length += edges_length(mesh, f.silhouette_edges);
            View& v = session.visibility(cams[i]);
            r.visibility_s += v.drawing.stats.seconds_visibility;
            r.wrong_px += wrong_length_px(mesh, cams[i], ref_visible[i], visible_intervals(v));
            progress->advance();
        }
    progress->finish();
    for (const Row& r : rows)
        std::fprintf(stderr, "  %s %g%s: %.3f ms/frame, recall %.4f\n", r.finder.c_str(), r.fraction,
                     r.coherence ? " +coherence" : "", 1e3 * r.features_s / double(cams.size()),
                     ref_total > 0.0 ? r.found_length / ref_total : 1.0);

    const double n = double(cams.size());
    const double exhaustive_ms = 1e3 * rows[0].features_s / n, exhaustive_search_ms = 1e3 * rows[0].search_s / n;
    const double exhaustive_median = median(rows[0].search_frames);
    std::string csv =
        "model,triangles,finder,fraction,coherence,frames,ms_per_frame,silhouette_edges_per_frame,"
        "silhouette_edges_per_second,recall_length,wrong_visible_length_px\n";
    std::string path_note = a.path;
    if (a.path == "orbit") path_note += " " + fmt("%g", a.arc / a.frames) + " deg/frame";
    path_note += ", " + std::to_string(a.threads) + (a.threads > 1 ? " threads" : " thread");
    if (a.first_full) path_note += ", coherence from an exhaustive first view";
    std::string md = "### " + name + " (" + std::to_string(nf) + " triangles, " + path_note + ", " +
                     std::to_string(a.frames) + " frames)\n\n"
                     "| finder | fraction | coherence | ms/frame | frames/s | triangles/s | silhouette edges/frame | "
                     "silhouette edges/s | recall (length) | wrong visible px/frame | slowdown of exhaustive | "
                     "search ms/frame | search slowdown of exhaustive | visibility ms/frame | median search ms/frame | "
                     "median search slowdown of exhaustive | band faces/frame | faces turned/frame |\n"
                     "|---|---:|:---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    std::vector<PlotPoint> points;
    for (const Row& r : rows) {
        const double ms = 1e3 * r.features_s / n, fps = ms > 0.0 ? 1e3 / ms : 0.0;
        const double sil = r.silhouette_edges / n, sil_s = r.features_s > 0.0 ? r.silhouette_edges / r.features_s : 0.0;
        const double recall = ref_total > 0.0 ? r.found_length / ref_total : 1.0;
        const double wrong = r.wrong_px / n;
        csv += name + "," + std::to_string(nf) + "," + r.finder + "," + fmt("%g", r.fraction) + "," +
               (r.coherence ? "1" : "0") + "," + std::to_string(a.frames) + "," + fmt("%.6f", ms) + "," +
               fmt("%.1f", sil) + "," + fmt("%.0f", sil_s) + "," + fmt("%.6f", recall) + "," + fmt("%.3f", wrong) + "\n";
        md += "| " + r.finder + " | " + fmt("%g", r.fraction) + " | " + (r.coherence ? "yes" : "no") + " | " +
              fmt("%.3f", ms) + " | " + fmt("%.0f", fps) + " | " + fmt("%.3g", fps * double(nf)) + " | " +
              fmt("%.0f", sil) + " | " + fmt("%.3g", sil_s) + " | " + fmt("%.4f", recall) + " | " +
              fmt("%.1f", wrong) + " | " + fmt("%.2f", ms > 0.0 ? exhaustive_ms / ms : 0.0) + " | " +
              fmt("%.3f", 1e3 * r.search_s / n) + " | " +
              fmt("%.2f", r.search_s > 0.0 ? exhaustive_search_ms / (1e3 * r.search_s / n) : 0.0) + " | " +
              fmt("%.2f", 1e3 * r.visibility_s / n) + " | " + fmt("%.3f", 1e3 * median(r.search_frames)) + " | " +
              fmt("%.2f", median(r.search_frames) > 0.0 ? exhaustive_median / median(r.search_frames) : 0.0) + " | " +
              fmt("%.0f", r.band_faces / n) + " | " + fmt("%.0f", r.faces_turned / n) + " |\n";
        PlotPoint p;
        p.x = recall;
        p.y = ms;
        p.series = r.finder == "exhaustive" ? 0 : r.coherence ? 2 : 1;
        p.label = r.finder == "exhaustive" ? "exhaustive" : fmt("%g", r.fraction);
        points.push_back(p);
    }
    std::fputs(md.c_str(), stdout);
    if (!a.csv.empty()) write_text_file(a.csv, csv);
    if (!a.markdown.empty()) write_text_file(a.markdown, md);
    if (!a.plot.empty())
        write_text_file(a.plot, scatter_plot_svg(points, name + ": finder time against recall (" + a.path + ")",
                                                 "recall of silhouette length", "ms per frame (finder, cusps, chaining)",
                                                 {"exhaustive", "randomized", "randomized + coherence"}));
    return 0;
}

}  // namespace inkline
