// Detail control, multi-scale method (src/detail/): per model the pre-process (time, memory per
// vertex and level) and a dolly from the framed view to 8x farther, per frame the visible line
// length, the model's image area and the time of a frame with and without detail; then a slow
// dolly (1 % of the distance a frame) for temporal coherence: the symmetric difference of
// consecutive drawings' visible lines, counting only what is more than 1 px from the other
// drawing's lines. Times are the thread's CPU time on one core (a shared machine's wall time
// mostly measures the others). Prints Markdown.
// Usage: bench_multiscale [--frames=N] [--target=PX] [--ratio=R] [--relax=A] [--spread=S]
//        [--second-order] [--sweeps=N] [--tangential=N]
//        [--smoothing=T1] [--growth=G] [--order=1|2] [--thin=C] [--no-coherence] [--write-levels=DIR] [--plot=FILE.svg] [MODEL ...]
// (default armadillo bunny00 elephant armadillo@1; MODEL@N: N rounds of Loop subdivision). Without
// --target, T is the projection of the mean edge length at the model's centre in the framed view.
// --write-levels writes each level as DIR/MODEL_Mk.off; --plot the density curves of the dolly.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "core/clock.hpp"
#include "bench_models.hpp"
#include "detail/multiscale.hpp"

namespace {

using namespace inkline;

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

double visible_length(const Drawing& d) {
    double sum = 0.0;
    for (const Piece& p : d.pieces)
        if (p.qi == 0)
            for (std::size_t i = 1; i < p.points.size(); ++i) sum += glm::length(p.points[i] - p.points[i - 1]);
    return sum;
}

// Visible lines sampled every half pixel, and a mask of the pixels within 1 px of them.
struct Raster {
    int w, h;
    std::vector<glm::dvec2> samples;
    std::vector<std::uint8_t> near;
    Raster(const Drawing& d, int width, int height) : w(width), h(height), near(std::size_t(w) * std::size_t(h), 0) {
        for (const Piece& p : d.pieces) {
            if (p.qi != 0) continue;
            for (std::size_t i = 1; i < p.points.size(); ++i) {
                const glm::dvec2 a = p.points[i - 1], b = p.points[i];
                const int n = std::max(1, int(std::ceil(2.0 * glm::length(b - a))));
                for (int k = 0; k < n; ++k) samples.push_back(a + (b - a) * ((double(k) + 0.5) / double(n)));
            }
        }
        for (const glm::dvec2& s : samples)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int x = int(std::floor(s.x)) + dx, y = int(std::floor(s.y)) + dy;
                    if (x >= 0 && y >= 0 && x < w && y < h) near[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 1;
                }
    }
    // Length (px) of this drawing's lines farther than about 1 px from the other's.
    double apart_from(const Raster& o) const {
        std::size_t n = 0;
        for (const glm::dvec2& s : samples) {
            const int x = int(std::floor(s.x)), y = int(std::floor(s.y));
            n += x < 0 || y < 0 || x >= w || y >= h || !o.near[std::size_t(y) * std::size_t(w) + std::size_t(x)];
        }
        return 0.5 * double(n);
    }
    double length() const { return 0.5 * double(samples.size()); }
};

ViewOptions line_options() {
    ViewOptions o;
    o.features.kinds[int(LineKind::Crease)] = false;  // the seed's lines: silhouettes, suggestive contours
    o.surface.suggestive = true;
    return o;
}

// Faces of level k whose normal turned over against the input's (folds of the smoothing), and
// the mean |k1| of level k over the vertices of no such face.
std::size_t flipped_faces(const Model& m, const MultiscaleLevels& L, int k, double* mean_away = nullptr) {
    const MeshTopology& t = m.topology();
    const std::vector<glm::dvec3> p = level_positions(m, L, k);
    std::size_t n = 0;
    std::vector<std::uint8_t> near(t.vertex_count(), 0);
    for (std::uint32_t f = 0; f < t.face_count(); ++f) {
        const auto& v = t.faces[f];
        const glm::dvec3 normal = glm::cross(p[v[1]] - p[v[0]], p[v[2]] - p[v[0]]);
        const bool flipped = glm::dot(normal, t.face_normal(f)) < 0.0;
        n += flipped;
        if (flipped) near[v[0]] = near[v[1]] = near[v[2]] = 1;
    }
    if (mean_away) {
        double sum = 0.0;
        std::size_t count = 0;
        for (std::size_t v = 0; v < t.vertex_count(); ++v) {
            const bool valid = k == 0 ? m.curvature().valid[v] != 0 : L.valid[L.at(k, v)] != 0;
            if (near[v] || !valid) continue;
            sum += std::fabs(k == 0 ? m.curvature().k1[v] : L.k1[L.at(k, v)]);
            ++count;
        }
        *mean_away = count ? sum / double(count) : 0.0;
    }
    return n;
}

// Level k of the model as an OFF file (to render and look at).
void write_level_off(const Model& m, const MultiscaleLevels& L, int k, const std::string& path) {
    const MeshTopology& t = m.topology();
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) return;
    std::fprintf(f, "OFF\n%zu %zu 0\n", t.vertex_count(), t.face_count());
    for (const glm::dvec3& p : level_positions(m, L, k)) std::fprintf(f, "%.9g %.9g %.9g\n", p.x, p.y, p.z);
    for (const auto& v : t.faces) std::fprintf(f, "3 %u %u %u\n", v[0], v[1], v[2]);
    std::fclose(f);
}

std::string g_write_levels;  // --write-levels=DIR

// The dolly's density curves of each model, for --plot.
struct Curve {
    std::string model;
    std::vector<double> factor, plain, detail;
};
std::vector<Curve> g_curves;

// The density curves as an SVG plot: distance (log scale, 1x to 8x) against visible length per
// image area relative to 1x (log scale), plain dashed and --detail solid, a colour per model.
void write_plot(const std::string& path) {
    const double w = 640, h = 440, left = 60, right = 150, top = 20, bottom = 50;
    const double pw = w - left - right, ph = h - top - bottom;
    double ymax = 1.0;
    for (const Curve& c : g_curves)
        for (double y : c.plain) ymax = std::max(ymax, y);
    ymax = std::pow(2.0, std::ceil(std::log2(ymax)));
    const auto x_of = [&](double f) { return left + pw * std::log2(f) / 3.0; };
    const auto y_of = [&](double d) { return top + ph * (1.0 - std::log2(std::max(d, 1e-9)) / std::log2(ymax)); };
    std::string svg;
    char line[512];
    const auto add = [&](const char* fmt, auto... args) {
        std::snprintf(line, sizeof line, fmt, args...);
        svg += line;
    };
    add("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" font-family=\"sans-serif\" font-size=\"12\">\n", w, h);
    add("<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n");
    for (double f : {1.0, 2.0, 4.0, 8.0}) {
        add("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n", x_of(f), top, x_of(f), top + ph);
        add("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%gx</text>\n", x_of(f), top + ph + 18, f);
    }
    for (double d = 1.0; d <= ymax; d *= 2.0) {
        add("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n", left, y_of(d), left + pw, y_of(d));
        add("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", left - 6, y_of(d) + 4, d);
    }
    add("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">camera distance (framed view = 1x)</text>\n", left + pw / 2, h - 10);
    add("<text transform=\"translate(16 %.1f) rotate(-90)\" text-anchor=\"middle\">line length per image area (1x = 1)</text>\n",
        top + ph / 2);
    const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e"};
    for (std::size_t i = 0; i < g_curves.size(); ++i) {
        const Curve& c = g_curves[i];
        const char* colour = colours[i % 5];
        for (int kind = 0; kind < 2; ++kind) {
            const std::vector<double>& ys = kind == 0 ? c.plain : c.detail;
            svg += "<polyline fill=\"none\" stroke=\"" + std::string(colour) + "\" stroke-width=\"2\"" +
                   (kind == 0 ? " stroke-dasharray=\"6 4\"" : "") + " points=\"";
            for (std::size_t k = 0; k < ys.size(); ++k) add("%.1f,%.1f ", x_of(c.factor[k]), y_of(ys[k]));
            svg += "\"/>\n";
        }
        const double y = top + 10 + 36.0 * double(i);
        add("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" stroke-width=\"2\" stroke-dasharray=\"6 4\"/>\n",
            w - right + 10, y, w - right + 34, y, colour);
        add("<text x=\"%.1f\" y=\"%.1f\">%s plain</text>\n", w - right + 40, y + 4, c.model.c_str());
        add("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" stroke-width=\"2\"/>\n", w - right + 10,
            y + 16, w - right + 34, y + 16, colour);
        add("<text x=\"%.1f\" y=\"%.1f\">%s --detail</text>\n", w - right + 40, y + 20, c.model.c_str());
    }
    svg += "</svg>\n";
    const std::string tmp = path + ".tmp";
    if (std::FILE* f = std::fopen(tmp.c_str(), "w")) {
        std::fputs(svg.c_str(), f);
        std::fclose(f);
        std::rename(tmp.c_str(), path.c_str());
    }
}

void bench(const std::string& name, int frames, double target_arg, const MultiscaleOptions& options, bool coherence) {
    const Model* m = bench_model_for(name, "bench_multiscale");
    if (!m) return;
    const MeshTopology& t = m->topology();
    // The model's own curvature and self-intersections (a plain render computes them too).
    double t0 = inkline::thread_cpu_seconds();
    m->curvature();
    m->self_intersections();
    m->rays();
    const double model_s = inkline::thread_cpu_seconds() - t0;
    t0 = inkline::thread_cpu_seconds();
    const MultiscaleLevels L = build_multiscale_levels(*m, options);
    const double levels_s = inkline::thread_cpu_seconds() - t0;
    const double per_vertex_level = L.levels > 1 ? double(L.bytes()) / double(L.vertices * std::size_t(L.levels - 1)) : 0.0;
    std::printf("\n## %s: %zu triangles, %zu vertices (r = %g)\n\n", name.c_str(), t.face_count(), t.vertex_count(), options.ratio);
    std::printf("pre-process: %.2f s CPU (+ %.2f s for the model's curvature, self-intersections and ray index), "
                "%d levels, %zu collapses, %.1f bytes a vertex a level (%.1f MB), mean edge %.4g%s%s\n",
                levels_s, model_s, L.levels, L.collapses, per_vertex_level, double(L.bytes()) / 1e6, L.feature_size,
                L.note.empty() ? "" : ", ", L.note.c_str());
    std::printf("\n| level | mean abs k1 | median abs k1 | faces turned over | mean abs k1 away from them |\n|---|---|---|---|---|\n");
    for (int k = 0; k < L.levels; ++k) {
        double away = 0.0;
        const std::size_t flipped = flipped_faces(*m, L, k, &away);
        std::printf("| M%d | %.4g | %.4g | %zu | %.4g |", k, L.mean_abs_k1[std::size_t(k)], L.median_abs_k1[std::size_t(k)],
                    flipped, away);
        if (std::getenv("MSD_PCT")) {
            std::vector<float> a;
            for (std::size_t v = 0; v < L.vertices; ++v) a.push_back(std::fabs(k == 0 ? m->curvature().k1[v] : L.k1[L.at(k, v)]));
            std::sort(a.begin(), a.end());
            double top = 0.0;
            for (std::size_t i = a.size() * 99 / 100; i < a.size(); ++i) top += a[i];
            std::printf(" p90 %.3g p99 %.3g p99.9 %.3g max %.3g, top 1%% share of sum %.2f |", a[a.size() * 9 / 10], a[a.size() * 99 / 100],
                        a[a.size() * 999 / 1000], a.back(), top / (L.mean_abs_k1[std::size_t(k)] * double(a.size())));
        }
        std::printf("\n");
    }
    if (!g_write_levels.empty())
        for (int k = 0; k < L.levels; ++k) write_level_off(*m, L, k, g_write_levels + "/" + name + "_M" + std::to_string(k) + ".off");
    const Camera framed = Camera::framing(t.bounds, 1024, 1024);
    const glm::dvec3 c = t.bounds.center(), offset = framed.eye() - c;
    const double target = target_arg > 0.0 ? target_arg : L.feature_size * framed.focal() / glm::length(offset);
    MultiscaleSession detail(*m, L, line_options(), {.target_px = target});
    ViewSession plain(*m, line_options());
    auto camera_at = [&](double factor) { return Camera::perspective(c + factor * offset, c, {0, 1, 0}, 30.0, 1024, 1024); };
    detail.render(camera_at(1.0));  // warm: storage and the blended model's ray index
    plain.render(camera_at(1.0));
    std::printf("\nT = %.2f px. Dolly from the framed view (1x) to 8x: visible length per image area of the model "
                "(bounding sphere), relative to 1x; frame times in ms (CPU, one core).\n\n",
                target);
    std::printf("| distance | plain length px | detail length px | plain density | detail density | plain ms | detail ms |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    double d0p = 0.0, d0d = 0.0;
    Curve curve{name, {}, {}, {}};
    std::vector<double> plain_ms, detail_ms;
    for (int i = 0; i < frames; ++i) {
        const double factor = std::pow(8.0, double(i) / double(frames - 1));
        const Camera cam = camera_at(factor);
        double s = inkline::thread_cpu_seconds();
        const double lp = visible_length(plain.render(cam).drawing);
        plain_ms.push_back(1e3 * (inkline::thread_cpu_seconds() - s));
        s = inkline::thread_cpu_seconds();
        const double ld = visible_length(detail.render(cam).drawing);
        detail_ms.push_back(1e3 * (inkline::thread_cpu_seconds() - s));
        const double r = t.bounds.half_diagonal() * cam.focal() / (factor * glm::length(offset));
        const double area = M_PI * r * r;
        if (i == 0) d0p = lp / area, d0d = ld / area;
        std::printf("| %.2fx | %.0f | %.0f | %.2f | %.2f | %.2f | %.2f |\n", factor, lp, ld, lp / area / d0p,
                    ld / area / d0d, plain_ms.back(), detail_ms.back());
        curve.factor.push_back(factor);
        curve.plain.push_back(lp / area / d0p);
        curve.detail.push_back(ld / area / d0d);
    }
    g_curves.push_back(std::move(curve));
    std::printf("\nmedian frame: plain %.2f ms, detail %.2f ms\n", median(plain_ms), median(detail_ms));
    if (!coherence) return;
    // Temporal coherence: 20 frames from 2x outward, 1 % farther each.
    double worst = 0.0, sum = 0.0, sum_plain = 0.0;
    std::unique_ptr<Raster> prev, prev_plain;
    for (int i = 0; i <= 20; ++i) {
        const Camera cam = camera_at(2.0 * std::pow(1.01, i));
        auto now = std::make_unique<Raster>(detail.render(cam).drawing, 1024, 1024);
        auto now_plain = std::make_unique<Raster>(plain.render(cam).drawing, 1024, 1024);
        if (prev) {
            const double diff = (now->apart_from(*prev) + prev->apart_from(*now)) / std::max(1.0, now->length());
            const double diff_plain = (now_plain->apart_from(*prev_plain) + prev_plain->apart_from(*now_plain)) /
                                      std::max(1.0, now_plain->length());
            worst = std::max(worst, diff);
            sum += diff;
            sum_plain += diff_plain;
        }
        prev = std::move(now);
        prev_plain = std::move(now_plain);
    }
    std::printf("slow dolly (1 %% a frame from 2x): symmetric difference beyond 1 px, per frame, as a share of the "
                "drawing's length: detail mean %.3f (worst %.3f), plain mean %.3f\n",
                sum / 20.0, worst, sum_plain / 20.0);
}

}  // namespace

int main(int argc, char** argv) {
    int frames = 13;
    double target = 0.0;
    MultiscaleOptions options;
    bool coherence = true;
    std::string plot;
    std::vector<std::string> models;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a.rfind("--frames=", 0) == 0) frames = std::max(2, std::stoi(a.substr(9)));
        else if (a.rfind("--target=", 0) == 0) target = std::stod(a.substr(9));
        else if (a.rfind("--ratio=", 0) == 0) options.ratio = std::stod(a.substr(8));
        else if (a.rfind("--relax=", 0) == 0) options.relax = std::stod(a.substr(8));
        else if (a.rfind("--spread=", 0) == 0) options.spread = std::stod(a.substr(9));
        else if (a == "--no-coherence") coherence = false;
        else if (a.rfind("--write-levels=", 0) == 0) g_write_levels = a.substr(15);
        else if (a.rfind("--plot=", 0) == 0) plot = a.substr(7);
        else if (a == "--second-order") options.fairing = MultiscaleFairing::SecondOrder;
        else if (a.rfind("--sweeps=", 0) == 0) options.sweeps = std::stoi(a.substr(9));
        else if (a.rfind("--tangential=", 0) == 0) options.tangential_sweeps = std::stoi(a.substr(13));
        else if (a.rfind("--smoothing=", 0) == 0) options.smoothing = std::stod(a.substr(12));
        else if (a.rfind("--growth=", 0) == 0) options.smoothing_growth = std::stod(a.substr(9));
        else if (a.rfind("--order=", 0) == 0) options.smoothing_order = std::stoi(a.substr(8));
        else if (a.rfind("--thin=", 0) == 0) options.thin_guard = std::stod(a.substr(7));
        else models.push_back(a);
    }
    if (models.empty()) models = {"armadillo", "bunny00", "elephant", "armadillo@1"};
    std::printf("# Multi-scale detail: pre-process and dolly (bench_multiscale)\n");
    for (const std::string& m : models) bench(m, frames, target, options, coherence);
    if (!plot.empty()) write_plot(plot);
    return 0;
}
