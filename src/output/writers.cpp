#include "output/writers.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string_view>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "output/cairo_api.hpp"
#include "style/strokes.hpp"

namespace inkline {
namespace {

// ---- What is drawn, and how: one table shared by SVG and Cairo ----------------------------

struct LineStyle {
    const char* name;          // layer id suffix: "<kind>-<name>"
    std::uint32_t rgb;         // 0xRRGGBB
    double dash_on, dash_off;  // 0, 0: solid
    double width_scale;        // times the visible line width
};

constexpr std::array<LineStyle, 4> kStyles{{
    {"visible", 0x000000, 0, 0, 1.0},         // QI 0
    {"hidden-qi1", 0x7f7f7f, 6, 4, 0.6},      // QI 1
    {"hidden-qi2", 0xa8a8a8, 2, 3, 0.5},      // QI 2
    {"hidden-qi3plus", 0xcccccc, 1, 4, 0.4},  // QI >= 3
}};

double line_width(const Drawing& d, const OutputOptions& o) {
    return o.line_width > 0 ? o.line_width : std::max(1.0, 1.5 * d.camera.height() / 1024.0);
}

bool is_written(const Piece& p, const OutputOptions& o) {
    if (p.points.size() < 2 || p.qi < 0 || (p.qi > 0 && !o.hidden)) return false;
    return std::all_of(p.points.begin(), p.points.end(), [](const glm::dvec2& q) {
        return std::isfinite(q.x) && std::isfinite(q.y);
    });
}

ChainOptions chain_options(const OutputOptions& o) {
    ChainOptions c;
    c.hidden = o.hidden;
    c.keep_specks = o.keep_specks;
    return c;
}

int level_of(int qi) { return std::min<int>(qi, int(kStyles.size()) - 1); }

// One Inkscape layer: the strokes of one kind at one QI level, by object, then in chain order.
struct Layer {
    const LineStyle& style;
    LineKind kind;
    std::vector<const Stroke*> strokes;
    std::string id() const { return std::string(to_string(kind)) + "-" + style.name; }
};

// Non-empty layers in drawing order: deepest hidden level first, visible last; kinds in enum order.
std::vector<Layer> layers(const std::vector<Stroke>& strokes) {
    std::vector<Layer> out;
    for (int level = int(kStyles.size()) - 1; level >= 0; --level) {
        for (int k = 0; k < kPieceKindCount; ++k) {
            Layer g{kStyles[std::size_t(level)], LineKind(k), {}};
            for (const Stroke& s : strokes)
                if (s.kind == g.kind && level_of(s.qi) == level) g.strokes.push_back(&s);
            std::stable_sort(g.strokes.begin(), g.strokes.end(),
                             [](const Stroke* a, const Stroke* b) { return a->object < b->object; });
            if (!g.strokes.empty()) out.push_back(std::move(g));
        }
    }
    return out;
}

// Colour of a layer: the level's grey for hidden lines, the kind's colour for visible ones.
std::uint32_t layer_rgb(const Layer& g) { return &g.style == &kStyles[0] ? kind_rgb(g.kind) : g.style.rgb; }

// Whether a stroke's pieces carry an opacity per point (tone lines): drawn run by run.
bool has_opacity(const Stroke& s, const Drawing& d) {
    return !s.pieces.empty() && !d.pieces[s.pieces[0]].opacity.empty();
}

// A run of a tone line's segments of one opacity and one width factor.
struct OpacityRun {
    std::vector<glm::dvec2> points;
    double alpha = 1.0, width = 1.0;
};

// A piece with opacity (and width factor, when it has one) per point as runs of segments of one
// opacity and width (the mean of a segment's ends, in steps of 1/16: a run per change keeps files
// small). Empty for an opaque piece.
std::vector<OpacityRun> opacity_runs(const Piece& p) {
    std::vector<OpacityRun> runs;
    if (p.opacity.size() != p.points.size()) return runs;
    const bool widths = p.width.size() == p.points.size();
    const auto level = [](const std::vector<float>& v, std::size_t i) {
        return int(std::lround(std::clamp(0.5 * (double(v[i - 1]) + double(v[i])), 0.0, 1.0) * 16.0));
    };
    int last_alpha = -1, last_width = -1;
    for (std::size_t i = 1; i < p.points.size(); ++i) {
        const int a = level(p.opacity, i), w = widths ? level(p.width, i) : 16;
        if (a != last_alpha || w != last_width || runs.empty()) {
            runs.push_back({{p.points[i - 1]}, a / 16.0, std::max(w, 1) / 16.0});
            last_alpha = a, last_width = w;
        }
        runs.back().points.push_back(p.points[i]);
    }
    std::erase_if(runs, [](const OpacityRun& r) { return r.alpha <= 0.0; });
    return runs;
}

// Liang-Barsky: clips segment a-b to the box [lo, hi]; false when nothing is left (or the
// arithmetic overflowed). An endpoint inside the box is kept bit-exact.
bool clip(glm::dvec2& a, glm::dvec2& b, const glm::dvec2& lo, const glm::dvec2& hi) {
    const glm::dvec2 d = b - a;
    double t0 = 0, t1 = 1;
    for (int i = 0; i < 2; ++i) {
        const double p[2] = {-d[i], d[i]}, q[2] = {a[i] - lo[i], hi[i] - a[i]};
        for (int k = 0; k < 2; ++k) {
            if (p[k] == 0 && q[k] < 0) return false;
            if (p[k] < 0) t0 = std::max(t0, q[k] / p[k]);
            if (p[k] > 0) t1 = std::min(t1, q[k] / p[k]);
        }
    }
    if (!(t0 <= t1)) return false;
    const glm::dvec2 a0 = a;
    if (t0 > 0) a = a0 + t0 * d;
    if (t1 < 1) b = a0 + t1 * d;
    const auto inside = [&](const glm::dvec2& v) {
        return v.x >= lo.x - 1 && v.x <= hi.x + 1 && v.y >= lo.y - 1 && v.y <= hi.y + 1;
    };
    return inside(a) && inside(b);
}

// The parts of a polyline inside the image grown by an image-sized margin. Cairo's
// 24.8 fixed point wraps beyond about 8e6 px (and so do SVG renderers built on it), which
// projections of points near the eye plane easily reach.
std::vector<std::vector<glm::dvec2>> clipped_runs(const std::vector<glm::dvec2>& points, const Camera& cam) {
    const double m = std::max(cam.width(), cam.height());
    const glm::dvec2 lo(-m, -m), hi(cam.width() + m, cam.height() + m);
    std::vector<std::vector<glm::dvec2>> runs;
    bool open = false;  // the last run ends at points[i - 1]
    for (std::size_t i = 1; i < points.size(); ++i) {
        glm::dvec2 a = points[i - 1], b = points[i];
        if (!clip(a, b, lo, hi)) {
            open = false;
            continue;
        }
        if (!open) runs.push_back({a});
        runs.back().push_back(b);
        open = b == points[i];
    }
    return runs;
}

// ---- Atomic file: "<target>.tmp-XXXXXX" renamed onto the target by commit() ----------------

mode_t process_umask() {  // without the race of umask(umask(0))
    std::ifstream in("/proc/self/status");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("Umask:", 0) == 0) return mode_t(std::stoul(line.substr(6), nullptr, 8));
    return 022;
}

class TempFile {
public:
    explicit TempFile(std::string target)
        : target_(std::move(target)), path_(target_ + ".tmp-XXXXXX") {
        fd_ = ::mkstemp(path_.data());
        if (fd_ < 0) fail(errno);
        ::fchmod(fd_, 0666 & ~process_umask());  // mkstemp's 0600 is wrong for an output file
    }
    ~TempFile() {
        if (fd_ >= 0) ::close(fd_);
        if (!committed_) ::unlink(path_.c_str());
    }
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;

    // Appends; on failure remembers errno and returns false.
    bool write(const void* data, std::size_t n) {
        for (auto* p = static_cast<const char*>(data); n > 0;) {
            const ssize_t k = ::write(fd_, p, n);
            if (k < 0 && errno == EINTR) continue;
            if (k < 0) return error_ = errno, false;
            p += k;
            n -= std::size_t(k);
        }
        return true;
    }
    void write_all(std::string_view s) {
        if (!write(s.data(), s.size())) fail(error_);
    }
    void commit() {
        if (::fsync(fd_) != 0) fail(errno);  // the destructor closes and unlinks
        if (::close(std::exchange(fd_, -1)) != 0) fail(errno);
        if (std::rename(path_.c_str(), target_.c_str()) != 0) fail(errno);
        committed_ = true;
    }
    int error() const { return error_; }
    [[noreturn]] void fail(int err) const {
        throw Error(target_, std::string("cannot write: ") + std::strerror(err));
    }
    [[noreturn]] void fail(const std::string& reason) const { throw Error(target_, reason); }

private:
    std::string target_, path_;
    int fd_ = -1;
    int error_ = 0;
    bool committed_ = false;
};

// ---- SVG ---------------------------------------------------------------------------------

// Locale-independent: 6 significant digits by default, fixed `decimals` for coordinates.
std::string num(double v, int decimals = -1) {
    char buf[400];  // fixed notation of any double fits
    char* end = buf + sizeof buf;
    const auto r = decimals < 0 ? std::to_chars(buf, end, v, std::chars_format::general, 6)
                                : std::to_chars(buf, end, v, std::chars_format::fixed, decimals);
    return std::string(buf, r.ptr);
}

// ---- Cairo -------------------------------------------------------------------------------

using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using ContextPtr = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

cairo_status_t append_bytes(void* closure, const unsigned char* data, unsigned int length) {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

}  // namespace

// The drawing's base layer (RGB24, same size) painted over the whole surface.
void paint_raster_layer(cairo_t* c, const RasterLayer& base) {
    SurfacePtr image(cairo_api().image_surface_create(CAIRO_FORMAT_RGB24, base.width, base.height), cairo_api().surface_destroy);
    cairo_api().surface_flush(image.get());
    unsigned char* data = cairo_api().image_surface_get_data(image.get());
    const int stride = cairo_api().image_surface_get_stride(image.get());
    if (!data) return;
    for (int y = 0; y < base.height; ++y)
        std::memcpy(data + std::size_t(y) * std::size_t(stride), &base.rgb[std::size_t(y) * std::size_t(base.width)],
                    std::size_t(base.width) * 4);
    cairo_api().surface_mark_dirty(image.get());
    cairo_api().set_source_surface(c, image.get(), 0, 0);
    cairo_api().paint(c);
}

// The base layer as an SVG <image> (a PNG inline), Inkscape layer "base".
std::string svg_raster_layer(const RasterLayer& base) {
    SurfacePtr image(cairo_api().image_surface_create(CAIRO_FORMAT_RGB24, base.width, base.height), cairo_api().surface_destroy);
    ContextPtr cr(cairo_api().create(image.get()), cairo_api().destroy);
    paint_raster_layer(cr.get(), base);
    std::string png;
    cairo_api().surface_write_to_png_stream(image.get(), append_bytes, &png);
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string b64;
    for (std::size_t i = 0; i < png.size(); i += 3) {
        const std::uint32_t n = (std::uint32_t(std::uint8_t(png[i])) << 16) |
                                (i + 1 < png.size() ? std::uint32_t(std::uint8_t(png[i + 1])) << 8 : 0) |
                                (i + 2 < png.size() ? std::uint32_t(std::uint8_t(png[i + 2])) : 0);
        b64 += k[(n >> 18) & 63];
        b64 += k[(n >> 12) & 63];
        b64 += i + 1 < png.size() ? k[(n >> 6) & 63] : '=';
        b64 += i + 2 < png.size() ? k[n & 63] : '=';
    }
    const std::string w = std::to_string(base.width), h = std::to_string(base.height);
    return "<g id=\"base\" inkscape:groupmode=\"layer\" inkscape:label=\"base\">\n<image x=\"0\" y=\"0\" width=\"" + w +
           "\" height=\"" + h + "\" href=\"data:image/png;base64," + b64 + "\"/>\n</g>\n";
}

namespace {

// `one_path_per_stroke` (PDF): each stroke its own path object, so an editor selects strokes, not a
// whole layer as one compound path; PNG strokes a layer at once (the same pixels, fewer calls).
cairo_status_t draw_cairo(cairo_surface_t* surface, const Drawing& d, const std::vector<Stroke>& strokes,
                          const OutputOptions& o, bool background, bool one_path_per_stroke) {
    ContextPtr cr(cairo_api().create(surface), cairo_api().destroy);
    cairo_t* c = cr.get();
    if (background) {
        cairo_api().set_source_rgb(c, 1, 1, 1);
        cairo_api().paint(c);
    }
    if (!d.base.empty()) paint_raster_layer(c, d.base);
    cairo_api().set_line_cap(c, CAIRO_LINE_CAP_ROUND);
    cairo_api().set_line_join(c, CAIRO_LINE_JOIN_ROUND);
    const double width = line_width(d, o);
    for (const Layer& g : layers(strokes)) {
        const std::uint32_t rgb = layer_rgb(g);
        const auto channel = [&](int shift) { return ((rgb >> shift) & 0xff) / 255.0; };
        cairo_api().set_source_rgb(c, channel(16), channel(8), channel(0));
        cairo_api().set_line_width(c, width * g.style.width_scale * kind_width(g.kind));
        const double dash[2] = {g.style.dash_on, g.style.dash_off};
        cairo_api().set_dash(c, dash, g.style.dash_on > 0 ? 2 : 0, 0);
        for (const Stroke* s : g.strokes) {
            if (has_opacity(*s, d)) continue;  // drawn run by run below
            for (const auto& run : clipped_runs(s->path.points(), d.camera)) {
                const bool closed = run.size() > 2 && run.front() == run.back();
                cairo_api().move_to(c, run[0].x, run[0].y);
                for (std::size_t i = 1; i + (closed ? 1 : 0) < run.size(); ++i) cairo_api().line_to(c, run[i].x, run[i].y);
                if (closed) cairo_api().close_path(c);
                if (one_path_per_stroke) cairo_api().stroke(c);
            }
        }
        cairo_api().stroke(c);
        for (const Stroke* s : g.strokes) {
            if (!has_opacity(*s, d)) continue;
            const double layer_width = cairo_api().get_line_width(c);
            for (std::uint32_t i : s->pieces)
                for (const auto& [run, alpha, run_width] : opacity_runs(d.pieces[i])) {
                    cairo_api().set_source_rgba(c, channel(16), channel(8), channel(0), alpha);
                    cairo_api().set_line_width(c, layer_width * run_width);
                    for (const auto& clipped : clipped_runs(run, d.camera)) {
                        cairo_api().move_to(c, clipped[0].x, clipped[0].y);
                        for (std::size_t k = 1; k < clipped.size(); ++k) cairo_api().line_to(c, clipped[k].x, clipped[k].y);
                    }
                    cairo_api().stroke(c);
                }
            cairo_api().set_line_width(c, layer_width);
        }
    }
    return cairo_api().status(c);
}

cairo_status_t to_temp(void* closure, const unsigned char* data, unsigned int length) {
    return static_cast<TempFile*>(closure)->write(data, length) ? CAIRO_STATUS_SUCCESS
                                                                : CAIRO_STATUS_WRITE_ERROR;
}

// Streams through TempFile rather than letting Cairo open the file: one write path, and a
// failed write reports the real errno instead of Cairo's generic WRITE_ERROR.
void write_cairo(const Drawing& d, const std::vector<Stroke>& strokes, Format f, const OutputOptions& o,
                 TempFile& file) {
    const int w = d.camera.width(), h = d.camera.height();
    SurfacePtr surface(f == Format::Pdf
                           ? cairo_api().pdf_surface_create_for_stream(to_temp, &file, w, h)
                           : cairo_api().image_surface_create(CAIRO_FORMAT_RGB24, w, h),
                       cairo_api().surface_destroy);
    cairo_surface_t* s = surface.get();
    cairo_status_t st = cairo_api().surface_status(s);
    if (st == CAIRO_STATUS_SUCCESS) st = draw_cairo(s, d, strokes, o, f == Format::Png, f == Format::Pdf);
    if (st == CAIRO_STATUS_SUCCESS && f == Format::Png) {
        st = cairo_api().surface_write_to_png_stream(s, to_temp, &file);
    } else if (st == CAIRO_STATUS_SUCCESS) {
        cairo_api().surface_finish(s);
        st = cairo_api().surface_status(s);
    }
    if (file.error() != 0) file.fail(file.error());
    if (st != CAIRO_STATUS_SUCCESS) file.fail(std::string("cairo: ") + cairo_api().status_to_string(st));
}

}  // namespace

Format output_format(const std::string& path, const std::string& explicit_format) {
    std::string name = explicit_format;
    if (name.empty()) {
        name = std::filesystem::path(path).extension().string();
        if (!name.empty()) name.erase(0, 1);
    }
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char ch) { return char(std::tolower(ch)); });
    constexpr std::pair<std::string_view, Format> kNames[] = {
        {"svg", Format::Svg}, {"pdf", Format::Pdf}, {"png", Format::Png}, {"json", Format::Json}};
    for (const auto& [n, f] : kNames)
        if (name == n) return f;
    throw Error(explicit_format.empty() ? path : "--format",
                "unknown output format '" + name + "' (expected svg, pdf, png or json)");
}

namespace {
// specks: what SVG, PDF and PNG of these options leave out (the JSON keeps every piece).
std::string json_of(const Drawing& d, const OutputOptions& o, std::size_t specks) {
    using json = nlohmann::ordered_json;
    const auto vec3 = [](const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); };
    const Camera& cam = d.camera;
    json camera = {{"eye", vec3(cam.eye())}, {"target", vec3(cam.target())},
                   {"up", vec3(cam.up())}, {"fov", cam.fov_deg()}};
    if (cam.is_ortho()) camera["ortho"] = cam.ortho_height();
    const DrawingStats& s = d.stats;
    json stats = {{"triangles", s.triangles},
                  {"silhouette_edges", s.silhouette_edges},
                  {"border_edges", s.border_edges},
                  {"crease_edges", s.crease_edges},
                  {"curves", s.curves},
                  {"cusps", s.cusps},
                  {"crossings", s.crossings},
                  {"pieces", s.pieces},
                  {"ray_tests", s.ray_tests},
                  {"visibility", s.visibility},
                  {"clusters", s.clusters},
                  {"walks", s.walks},
                  {"cluster_decisions",
                   {{"bounding_box", s.clusters_bbox},
                    {"upper_bound", s.clusters_bounded},
                    {"occluded", s.clusters_occluded},
                    {"inconsistent", s.clusters_inconsistent}}},
                  {"finder", s.finder},
                  {"fraction", s.fraction},
                  {"seconds",
                   {{"load", s.seconds_load},
                    {"features", s.seconds_features},
                    {"visibility", s.seconds_visibility},
                    {"visibility_stages",
                     {{"pieces", s.seconds_pieces},
                      {"propagation", s.seconds_propagation},
                      {"walks", s.seconds_walks},
                      {"ray_tests", s.seconds_ray_tests}}},
                    {"output", s.seconds_output},
                    {"total", s.seconds_total}}}};
    if (s.recall >= 0.0) stats["recall_length"] = s.recall;
    if (s.seam_edges > 0) stats["orientation_seam_edges"] = s.seam_edges;  // (a non-orientable surface's repair)
    stats["specks_dropped"] = specks;
    if (s.seconds_tone_shade > 0.0)
        stats["seconds"]["tone"] = {{"shade", s.seconds_tone_shade},
                                    {"blur", s.seconds_tone_blur},
                                    {"ridges", s.seconds_tone_ridges},
                                    {"trace", s.seconds_tone_trace}};
    if (s.surface_curves > 0 || s.seconds_surface_lines > 0.0) {
        stats["surface_curves"] = s.surface_curves;
        stats["curvature_invalid_vertices"] = s.curvature_invalid_vertices;
        stats["seconds"]["surface_lines"] = s.seconds_surface_lines;
        stats["seconds"]["visibility_stages"]["surface_lines"] = s.seconds_surface_visibility;
    }
    json polylines = json::array();
    for (const Piece& p : d.pieces) {
        if (!is_written(p, o)) continue;
        json points = json::array();
        for (const glm::dvec2& q : p.points) points.push_back({q.x, q.y});
        json line = {{"kind", to_string(p.kind)}, {"qi", p.qi}};
        if (d.object_names.size() > 1)
            line["object"] = p.object < d.object_names.size() ? d.object_names[p.object] : std::string();
        line["points"] = std::move(points);
        if (!p.opacity.empty()) line["opacity"] = p.opacity;
        if (!p.width.empty()) line["width"] = p.width;
        polylines.push_back(std::move(line));
    }
    json root = {{"width", cam.width()}, {"height", cam.height()}, {"camera", std::move(camera)},
                 {"stats", std::move(stats)}, {"polylines", std::move(polylines)}};
    return root.dump() + "\n";
}
}  // namespace

// Text for an XML attribute value.
std::string xml_escape(const std::string& text) {
    std::string out;
    for (char ch : text) {
        switch (ch) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\n': out += "&#10;"; break;
            default: out += ch;
        }
    }
    return out;
}

std::string drawing_to_json(const Drawing& d, const OutputOptions& o) {
    std::size_t specks = 0;
    drawing_strokes(d, o, &specks);
    return json_of(d, o, specks);
}

namespace {


// Pixel coordinate for SVG: three decimals, trailing zeros dropped.
std::string coord(double v) {
    std::string t = num(v, 3);
    while (t.back() == '0') t.pop_back();
    if (t.back() == '.') t.pop_back();
    return t == "-0" ? "0" : t;
}

// One <path> per run of a stroke, with its kind, QI and object as attributes (class for
// Inkscape's Find and CSS selectors, data-* for scripts).
// `layer_width`: the group's stroke width (a tone line's run with a width factor sets its own).
void append_svg_paths(std::string& out, const Stroke& s, const Drawing& d, double layer_width) {
    const std::string kind = to_string(s.kind), qi = std::to_string(s.qi);
    std::string attrs = "class=\"" + kind + (s.qi == 0 ? " visible" : " hidden") + " qi" + qi + "\" data-kind=\"" +
                        kind + "\" data-qi=\"" + qi + "\"";
    if (d.object_names.size() > 1 && s.object < d.object_names.size())
        attrs += " data-object=\"" + xml_escape(d.object_names[s.object]) + "\"";
    const auto path = [&](const std::vector<glm::dvec2>& run, const std::string& more) {
        const bool closed = run.size() > 2 && run.front() == run.back();
        out += "<path " + attrs + more + " d=\"M" + coord(run[0].x) + "," + coord(run[0].y) + " L";
        for (std::size_t i = 1; i + (closed ? 1 : 0) < run.size(); ++i)
            out += coord(run[i].x) + "," + coord(run[i].y) + " ";
        out.pop_back();
        out += closed ? " Z\"/>\n" : "\"/>\n";
    };
    if (!has_opacity(s, d)) {
        for (const auto& run : clipped_runs(s.path.points(), d.camera)) path(run, "");
        return;
    }
    for (std::uint32_t i : s.pieces)  // tone lines: a path per run of one opacity (and width)
        for (const auto& [run, alpha, run_width] : opacity_runs(d.pieces[i]))
            for (const auto& clipped : clipped_runs(run, d.camera))
                path(clipped, (alpha < 1.0 ? " stroke-opacity=\"" + num(alpha) + "\"" : std::string()) +
                                  (run_width < 1.0 ? " stroke-width=\"" + num(layer_width * run_width, 4) + "\"" : std::string()));
}

std::string svg_of(const Drawing& d, const std::vector<Stroke>& strokes, const OutputOptions& o) {
    const std::string w = std::to_string(d.camera.width()), h = std::to_string(d.camera.height());
    std::string out =
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        "<svg xmlns=\"http://www.w3.org/2000/svg\" "
        "xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" version=\"1.1\" width=\"" +
        w + "\" height=\"" + h + "\" viewBox=\"0 0 " + w + " " + h + "\">\n" +
        "<rect id=\"background\" x=\"0\" y=\"0\" width=\"" + w + "\" height=\"" + h +
        "\" fill=\"#ffffff\"/>\n";
    if (!d.base.empty()) out += svg_raster_layer(d.base);
    const double width = line_width(d, o);
    const bool by_object = d.object_names.size() > 1;
    for (const Layer& g : layers(strokes)) {
        const std::string id = g.id();
        char color[8];
        std::snprintf(color, sizeof color, "#%06x", unsigned(layer_rgb(g)));
        out += "<g id=\"" + id + "\" inkscape:groupmode=\"layer\" inkscape:label=\"" + id +
               "\" fill=\"none\" stroke=\"" + color + "\" stroke-width=\"" +
               num(width * g.style.width_scale * kind_width(g.kind)) + "\"";
        if (g.style.dash_on > 0)
            out += " stroke-dasharray=\"" + num(g.style.dash_on) + "," + num(g.style.dash_off) +
                   "\"";
        out += " stroke-linecap=\"round\" stroke-linejoin=\"round\">\n";
        // Strokes come sorted by object: a group per object (several objects only).
        for (std::size_t i = 0; i < g.strokes.size();) {
            const std::uint32_t object = g.strokes[i]->object;
            if (by_object)
                out += "<g id=\"" + id + "-object" + std::to_string(object) + "\" inkscape:label=\"" +
                       xml_escape(object < d.object_names.size() ? d.object_names[object] : "") + "\">\n";
            for (; i < g.strokes.size() && g.strokes[i]->object == object; ++i)
                append_svg_paths(out, *g.strokes[i], d, width * g.style.width_scale * kind_width(g.kind));
            if (by_object) out += "</g>\n";
        }
        out += "</g>\n";
    }
    return out + "</svg>\n";
}

}  // namespace

std::vector<Stroke> drawing_strokes(const Drawing& d, const OutputOptions& o, std::size_t* specks_dropped) {
    ChainStats stats;
    std::vector<Stroke> strokes = chain_strokes(d, chain_options(o), nullptr, &stats);
    if (specks_dropped) *specks_dropped = stats.specks_dropped;
    return strokes;
}

std::string drawing_to_svg(const Drawing& d, const OutputOptions& o) {
    return svg_of(d, drawing_strokes(d, o), o);
}

WriteSummary write_drawing(const Drawing& d, const std::string& path, Format f, const OutputOptions& o) {
    WriteSummary summary;
    const std::vector<Stroke> strokes = drawing_strokes(d, o, &summary.specks_dropped);
    for (const Stroke& s : strokes) summary.strokes += clipped_runs(s.path.points(), d.camera).size();
    TempFile file(path);
    switch (f) {
        case Format::Json: file.write_all(json_of(d, o, summary.specks_dropped)); break;
        case Format::Svg: file.write_all(svg_of(d, strokes, o)); break;
        case Format::Pdf:
        case Format::Png: write_cairo(d, strokes, f, o, file); break;
    }
    file.commit();
    return summary;
}

void write_text_file(const std::string& path, const std::string& content) {
    TempFile file(path);
    file.write_all(content);
    file.commit();
}

namespace {
cairo_status_t append_to_string(void* closure, const unsigned char* data, unsigned int length) {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

// Round tick step: 1, 2 or 5 times a power of ten, about `count` steps over the span.
double tick_step(double span, int count) {
    const double raw = span / count, p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0})
        if (m * p >= raw) return m * p;
    return 10.0 * p;
}
}  // namespace

namespace {
constexpr double kPlotW = 720, kPlotH = 480, kPlotL = 80, kPlotR = 200, kPlotT = 50, kPlotB = 60;

// The plot's axes: ranges padded around the points, y on a log scale when the values span more
// than a factor of 20 (whole decades), else linear from 0; the ticks of y.
struct PlotAxes {
    double x0 = 1e300, x1 = -1e300, y0 = 0.0, y1 = 0.0;
    bool log_y = false;
    std::vector<double> yticks;
    double X(double x) const { return kPlotL + (x - x0) / (x1 - x0) * (kPlotW - kPlotL - kPlotR); }
    double Y(double y) const {
        const double t = log_y ? std::log10(std::max(y, y0) / y0) / std::log10(y1 / y0) : (y - y0) / (y1 - y0);
        return kPlotH - kPlotB - t * (kPlotH - kPlotT - kPlotB);
    }
};

PlotAxes plot_axes(const std::vector<PlotPoint>& points) {
    PlotAxes a;
    double ymin = 1e300, ymax = 0.0;
    for (const auto& p : points) {
        a.x0 = std::min(a.x0, p.x);
        a.x1 = std::max(a.x1, p.x);
        if (p.y > 0.0) ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
    }
    if (points.empty()) a.x0 = 0.0, a.x1 = 1.0;
    if (!(ymax > 0.0)) ymin = 1.0, ymax = 1.0;
    if (a.x1 - a.x0 < 1e-3) a.x0 -= 5e-4, a.x1 += 5e-4;
    const double xpad = 0.05 * (a.x1 - a.x0);
    a.x0 -= xpad;
    a.x1 += xpad;
    a.log_y = ymax / ymin > 20.0;
    a.y0 = a.log_y ? std::pow(10.0, std::floor(std::log10(ymin))) : 0.0;
    a.y1 = a.log_y ? std::pow(10.0, std::ceil(std::log10(ymax))) : ymax * 1.1;
    if (a.log_y) {
        for (double d = a.y0; d <= a.y1 * 1.0001; d *= 10.0)
            for (double m : {1.0, 2.0, 5.0})
                if (m * d <= a.y1 * 1.0001) a.yticks.push_back(m * d);
    } else {
        const double ys = tick_step(a.y1 - a.y0, 6);
        for (double y = 0.0; y <= a.y1 + 1e-12; y += ys) a.yticks.push_back(std::round(y / ys) * ys);
    }
    return a;
}
}  // namespace

std::string scatter_plot_svg(const std::vector<PlotPoint>& points, const std::string& title,
                             const std::string& x_label, const std::string& y_label,
                             const std::vector<std::string>& series_names) {
    constexpr double W = kPlotW, H = kPlotH, L = kPlotL, R = kPlotR, T = kPlotT, B = kPlotB;
    const PlotAxes axes = plot_axes(points);
    const double x0 = axes.x0, x1 = axes.x1;
    const bool log_y = axes.log_y;
    auto X = [&](double x) { return axes.X(x); };
    auto Y = [&](double y) { return axes.Y(y); };
    const std::vector<double>& yticks = axes.yticks;

    std::string svg;
    cairo_surface_t* surface = cairo_api().svg_surface_create_for_stream(append_to_string, &svg, W, H);
    cairo_t* cr = cairo_api().create(surface);
    cairo_api().set_source_rgb(cr, 1, 1, 1);
    cairo_api().paint(cr);
    cairo_api().select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    auto text = [&](double x, double y, const std::string& s, double size, double align) {
        cairo_api().set_font_size(cr, size);
        cairo_text_extents_t ext;
        cairo_api().text_extents(cr, s.c_str(), &ext);
        cairo_api().move_to(cr, x - align * ext.width, y);
        cairo_api().show_text(cr, s.c_str());
    };
    // Axes and ticks.
    cairo_api().set_source_rgb(cr, 0, 0, 0);
    cairo_api().set_line_width(cr, 1.0);
    cairo_api().move_to(cr, L, T);
    cairo_api().line_to(cr, L, H - B);
    cairo_api().line_to(cr, W - R, H - B);
    cairo_api().stroke(cr);
    const double xs = tick_step(x1 - x0, 6);
    char buf[64];
    for (double x = std::ceil(x0 / xs) * xs; x <= x1 + 1e-12; x += xs) {
        cairo_api().move_to(cr, X(x), H - B);
        cairo_api().line_to(cr, X(x), H - B + 5);
        cairo_api().stroke(cr);
        std::snprintf(buf, sizeof buf, "%g", std::round(x / xs) * xs);
        text(X(x), H - B + 18, buf, 11, 0.5);
    }
    for (double y : yticks) {
        cairo_api().set_source_rgb(cr, 0.88, 0.88, 0.88);
        cairo_api().move_to(cr, L, Y(y));
        cairo_api().line_to(cr, W - R, Y(y));
        cairo_api().stroke(cr);
        cairo_api().set_source_rgb(cr, 0, 0, 0);
        std::snprintf(buf, sizeof buf, "%g", y);
        text(L - 8, Y(y) + 4, buf, 11, 1.0);
    }
    text((L + W - R) / 2, H - 15, x_label, 13, 0.5);
    text(W / 2, 28, title, 15, 0.5);
    cairo_api().save(cr);
    cairo_api().translate(cr, 22, (T + H - B) / 2);
    cairo_api().rotate(cr, -M_PI / 2);
    text(0, 0, log_y ? y_label + " (log scale)" : y_label, 13, 0.5);
    cairo_api().restore(cr);
    // Points, labelled, coloured by series.
    static const double colours[][3] = {{0.1, 0.1, 0.1}, {0.85, 0.35, 0.1}, {0.1, 0.45, 0.8}, {0.2, 0.6, 0.2}};
    for (const auto& p : points) {
        const auto& c = colours[std::size_t(p.series) % 4];
        cairo_api().set_source_rgb(cr, c[0], c[1], c[2]);
        cairo_api().arc(cr, X(p.x), Y(p.y), 4.0, 0, 2 * M_PI);
        cairo_api().fill(cr);
        text(X(p.x) + 6, Y(p.y) - 6, p.label, 10, 0.0);
    }
    for (std::size_t i = 0; i < series_names.size(); ++i) {
        const auto& c = colours[i % 4];
        cairo_api().set_source_rgb(cr, c[0], c[1], c[2]);
        cairo_api().arc(cr, W - R + 20, T + 20 + 20 * double(i), 4.0, 0, 2 * M_PI);
        cairo_api().fill(cr);
        cairo_api().set_source_rgb(cr, 0, 0, 0);
        text(W - R + 30, T + 24 + 20 * double(i), series_names[i], 11, 0.0);
    }
    cairo_api().destroy(cr);
    cairo_api().surface_finish(surface);
    const cairo_status_t status = cairo_api().surface_status(surface);
    cairo_api().surface_destroy(surface);
    if (status != CAIRO_STATUS_SUCCESS) throw Error("plot", cairo_api().status_to_string(status));
    return svg;
}

}  // namespace inkline
