#include "output/styled.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

#include <glm/geometric.hpp>

#include "core/error.hpp"
#include "output/cairo_api.hpp"

namespace inkline {
namespace {

using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;

cairo_status_t append(void* closure, const unsigned char* data, unsigned int length) {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

void set_colour(cairo_t* c, std::uint32_t rgb, double opacity) {
    const auto ch = [&](int shift) { return ((rgb >> shift) & 0xff) / 255.0; };
    if (opacity >= 1.0)
        cairo_api().set_source_rgb(c, ch(16), ch(8), ch(0));
    else
        cairo_api().set_source_rgba(c, ch(16), ch(8), ch(0), opacity);
}

// Brush images by file, tinted with the ink colour (ARGB, premultiplied): a brush stroke fills
// its quads with the image as the source, which PDF and SVG keep as one embedded image and a
// small pattern per quad (a mask per quad would repeat a soft-mask group every time).
class Brushes {
public:
    cairo_surface_t* get(const std::string& path, std::uint32_t rgb) {
        const auto key = std::make_pair(path, rgb);
        auto it = cache_.find(key);
        if (it == cache_.end()) {
            SurfacePtr src(cairo_api().image_surface_create_from_png(path.c_str()), cairo_api().surface_destroy);
            if (cairo_api().surface_status(src.get()) != CAIRO_STATUS_SUCCESS)
                throw Error(path, std::string("cannot read brush image: ") +
                                      cairo_api().status_to_string(cairo_api().surface_status(src.get())));
            const int w = cairo_api().image_surface_get_width(src.get()), h = cairo_api().image_surface_get_height(src.get());
            SurfacePtr tinted(cairo_api().image_surface_create(CAIRO_FORMAT_ARGB32, w, h), cairo_api().surface_destroy);
            cairo_t* c = cairo_api().create(tinted.get());
            set_colour(c, rgb, 1.0);
            cairo_api().mask_surface(c, src.get(), 0, 0);  // alpha of the brush, colour of the ink
            cairo_api().destroy(c);
            it = cache_.emplace(key, std::move(tinted)).first;
        }
        return it->second.get();
    }

private:
    std::map<std::pair<std::string, std::uint32_t>, SurfacePtr> cache_;
};

// One quad of a brush stroke, filled with the brush image affinely mapped so that its x runs
// from u0 to u1 along the quad and its y across it.
void draw_quad(cairo_t* c, cairo_surface_t* brush, const BrushQuad& q) {
    const double iw = cairo_api().image_surface_get_width(brush), ih = cairo_api().image_surface_get_height(brush);
    const glm::dvec2 c0 = 0.5 * (q.corner[0] + q.corner[1]), c1 = 0.5 * (q.corner[2] + q.corner[3]);
    const double len = glm::length(c1 - c0);
    const double w = 0.5 * (glm::length(q.corner[0] - q.corner[1]) + glm::length(q.corner[3] - q.corner[2]));
    if (!(len > 1e-9) || !(w > 1e-9)) return;
    const glm::dvec2 d = (c1 - c0) / len, n(-d.y, d.x);
    // Grow the quad a little along the spine so neighbours overlap (no antialiasing seams); the image repeats there.
    const glm::dvec2 g = 0.3 * d;
    cairo_api().move_to(c, q.corner[0].x - g.x, q.corner[0].y - g.y);
    cairo_api().line_to(c, q.corner[1].x - g.x, q.corner[1].y - g.y);
    cairo_api().line_to(c, q.corner[2].x + g.x, q.corner[2].y + g.y);
    cairo_api().line_to(c, q.corner[3].x + g.x, q.corner[3].y + g.y);
    cairo_api().close_path(c);
    // User space -> image space: x = u0 iw + (d.(p - c0)) (u1 - u0) iw / len, y = ih/2 - n.(p - c0) ih / w
    // (the left side, corner 0, is at image row 0).
    const glm::dvec2 a = d * ((q.u1 - q.u0) * iw / len), b = -n * (ih / w);
    cairo_matrix_t m;
    cairo_api().matrix_init(&m, a.x, b.x, a.y, b.y, q.u0 * iw - glm::dot(a, c0), 0.5 * ih - glm::dot(b, c0));
    cairo_pattern_t* p = cairo_api().pattern_create_for_surface(brush);
    cairo_api().pattern_set_matrix(p, &m);
    cairo_api().pattern_set_extend(p, CAIRO_EXTEND_REPEAT);  // the brush tiles along x; PDF has no PAD
    cairo_api().pattern_set_filter(p, CAIRO_FILTER_GOOD);
    cairo_api().set_source(c, p);
    cairo_api().fill(c);
    cairo_api().pattern_destroy(p);
}

cairo_status_t draw(cairo_surface_t* surface, const StyledDrawing& sd, bool background, bool one_path_per_stroke = false) {
    cairo_t* c = cairo_api().create(surface);
    if (background) {
        set_colour(c, sd.background, 1.0);
        cairo_api().paint(c);
    }
    if (!sd.base.empty()) paint_raster_layer(c, sd.base);
    cairo_api().set_line_cap(c, CAIRO_LINE_CAP_ROUND);
    cairo_api().set_line_join(c, CAIRO_LINE_JOIN_ROUND);
    Brushes brushes;
    try {
        for (const StyledLayer& layer : sd.layers) {
            for (const Mark& m : layer.marks) {
                set_colour(c, m.rgb, m.opacity);
                switch (m.type) {
                    case Mark::Type::Stroke: {
                        cairo_api().set_line_width(c, m.width);
                        const double dash[2] = {m.dash_on, m.dash_off};
                        cairo_api().set_dash(c, dash, m.dash_on > 0 ? 2 : 0, 0);
                        for (const auto& path : m.paths) {
                            if (path.size() < 2) continue;
                            // As the default writers draw a stroke (output/writers.cpp): a closed one joined
                            // round where it starts; in PDF each its own path object, for editing.
                            const bool closed = path.size() > 2 && path.front() == path.back();
                            cairo_api().move_to(c, path[0].x, path[0].y);
                            for (std::size_t i = 1; i + (closed ? 1 : 0) < path.size(); ++i)
                                cairo_api().line_to(c, path[i].x, path[i].y);
                            if (closed) cairo_api().close_path(c);
                            if (one_path_per_stroke) cairo_api().stroke(c);
                        }
                        cairo_api().stroke(c);
                        break;
                    }
                    case Mark::Type::Fill:
                        cairo_api().set_fill_rule(c, CAIRO_FILL_RULE_WINDING);
                        for (const auto& path : m.paths) {
                            if (path.size() < 3) continue;
                            cairo_api().move_to(c, path[0].x, path[0].y);
                            for (std::size_t i = 1; i < path.size(); ++i) cairo_api().line_to(c, path[i].x, path[i].y);
                            cairo_api().close_path(c);
                        }
                        cairo_api().fill(c);
                        break;
                    case Mark::Type::Brush: {
                        cairo_surface_t* b = brushes.get(m.brush, m.rgb);
                        if (m.opacity < 1.0) cairo_api().push_group(c);
                        for (const BrushQuad& q : m.quads) draw_quad(c, b, q);
                        if (m.opacity < 1.0) {
                            cairo_api().pop_group_to_source(c);
                            cairo_api().paint_with_alpha(c, m.opacity);
                        }
                        break;
                    }
                }
            }
        }
    } catch (...) {
        cairo_api().destroy(c);
        throw;
    }
    const cairo_status_t st = cairo_api().status(c);
    cairo_api().destroy(c);
    return st;
}

// ---- SVG, written by hand: one Inkscape layer per StyledLayer (as the default writer), so an
// illustrator can edit the line classes apart. Brush strokes: the tinted brush image embedded once
// per (brush, colour) and, per quad, the columns of it that the quad shows mapped onto the quad.

std::string num(double v, int decimals = 3) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
    std::string out(buf, r.ptr);
    if (out.find('.') != std::string::npos) {
        while (out.back() == '0') out.pop_back();
        if (out.back() == '.') out.pop_back();
    }
    return out == "-0" ? "0" : out;
}

std::string hex_colour(std::uint32_t rgb) {
    char c[8];
    std::snprintf(c, sizeof c, "#%06x", unsigned(rgb & 0xffffff));
    return c;
}

std::string base64(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((in.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8 | (unsigned char)in[i + 2];
        out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
    }
    if (i + 1 == in.size()) {
        const unsigned v = (unsigned char)in[i] << 16;
        out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == in.size()) {
        const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8;
        out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
    }
    return out;
}

// One mark as SVG into body; brush images go into defs once per brush and colour.
class SvgMarks {
public:
    std::string defs;

    void add(std::string& body, const Mark& m) {
        const std::string colour = hex_colour(m.rgb);
        const std::string opacity = m.opacity < 1.0 ? " opacity=\"" + num(m.opacity) + "\"" : "";
        switch (m.type) {
            case Mark::Type::Stroke:
                body += "<g fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"" + num(m.width, 4) + "\"" + opacity;
                if (m.dash_on > 0) body += " stroke-dasharray=\"" + num(m.dash_on) + "," + num(m.dash_off) + "\"";
                body += " stroke-linecap=\"round\" stroke-linejoin=\"round\">\n";
                for (const auto& path : m.paths) {
                    if (path.size() < 2) continue;
                    body += "<polyline points=\"";
                    for (const glm::dvec2& q : path) body += num(q.x) + "," + num(q.y) + " ";
                    body.back() = '"';
                    body += "/>\n";
                }
                body += "</g>\n";
                break;
            case Mark::Type::Fill: {
                body += "<path fill=\"" + colour + "\" fill-rule=\"nonzero\" stroke=\"none\"" + opacity + " d=\"";
                for (const auto& path : m.paths) {
                    if (path.size() < 3) continue;
                    body += "M";
                    for (const glm::dvec2& q : path) body += num(q.x) + "," + num(q.y) + " ";
                    body += "Z";
                }
                body += "\"/>\n";
                break;
            }
            case Mark::Type::Brush: {
                cairo_surface_t* b = brushes.get(m.brush, m.rgb);
                const double iw = cairo_api().image_surface_get_width(b), ih = cairo_api().image_surface_get_height(b);
                auto [it, fresh] = brush_ids.emplace(std::make_pair(m.brush, m.rgb), "brush" + std::to_string(brush_ids.size()));
                if (fresh) {
                    std::string png;
                    cairo_api().surface_write_to_png_stream(b, append, &png);
                    defs += "<image id=\"" + it->second + "\" width=\"" + num(iw) + "\" height=\"" + num(ih) +
                            "\" href=\"data:image/png;base64," + base64(png) + "\"/>\n";
                }
                body += "<g" + opacity + ">\n";
                for (const BrushQuad& q : m.quads) {
                    const glm::dvec2 c0 = 0.5 * (q.corner[0] + q.corner[1]), c1 = 0.5 * (q.corner[2] + q.corner[3]);
                    const double len = glm::length(c1 - c0);
                    const double w = 0.5 * (glm::length(q.corner[0] - q.corner[1]) + glm::length(q.corner[3] - q.corner[2]));
                    if (!(len > 1e-9) || !(w > 1e-9) || !(q.u1 > q.u0)) continue;
                    const glm::dvec2 d = (c1 - c0) / len, n(-d.y, d.x);
                    // Image -> user space (the inverse of the Cairo pattern matrix in draw_quad):
                    // the image's columns u0 iw .. u1 iw, clipped by a nested <svg> viewport, land on
                    // the quad (a parallelogram from the start crossbar along the spine), grown by
                    // 0.3 px each way so neighbours overlap.
                    const glm::dvec2 A = d * (len / ((q.u1 - q.u0) * iw)), B = -n * (w / ih);
                    const glm::dvec2 e = c0 - A * (q.u0 * iw) - B * (0.5 * ih);
                    const double grow = 0.3 / glm::length(A);
                    const double x0 = q.u0 * iw - grow, x1 = q.u1 * iw + grow;
                    const auto g6 = [](double v) {
                        char buf[64];
                        const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 7);
                        return std::string(buf, r.ptr);
                    };
                    body += "<g transform=\"matrix(" + g6(A.x) + " " + g6(A.y) + " " + g6(B.x) + " " + g6(B.y) + " " +
                            g6(e.x) + " " + g6(e.y) + ")\"><svg x=\"" + g6(x0) + "\" y=\"0\" width=\"" + g6(x1 - x0) +
                            "\" height=\"" + num(ih) + "\" viewBox=\"" + g6(x0) + " 0 " + g6(x1 - x0) + " " + num(ih) +
                            "\"><use href=\"#" + it->second + "\"/>";
                    if (x0 < 0) body += "<use href=\"#" + it->second + "\" x=\"" + num(-iw) + "\"/>";   // wrap at seams
                    if (x1 > iw) body += "<use href=\"#" + it->second + "\" x=\"" + num(iw) + "\"/>";
                    body += "</svg></g>\n";
                }
                body += "</g>\n";
                break;
            }
        }
    }

private:
    Brushes brushes;
    std::map<std::pair<std::string, std::uint32_t>, std::string> brush_ids;
};

std::string styled_to_svg(const StyledDrawing& sd) {
    const std::string W = std::to_string(sd.width), H = std::to_string(sd.height);
    std::string body;
    SvgMarks marks;
    for (const StyledLayer& layer : sd.layers) {
        body += "<g id=\"" + layer.id + "\" inkscape:groupmode=\"layer\" inkscape:label=\"" + layer.id + "\">\n";
        // A group per object (scenes of several), in the scene's order as the plain writer has them.
        const bool by_object = sd.object_names.size() > 1;
        std::vector<std::uint32_t> objects;
        for (const Mark& m : layer.marks)
            if (std::find(objects.begin(), objects.end(), m.object) == objects.end()) objects.push_back(m.object);
        std::sort(objects.begin(), objects.end());
        for (const std::uint32_t object : objects) {
            if (by_object) {
                const std::string name = xml_escape(object < sd.object_names.size() ? sd.object_names[object] : "");
                body += "<g id=\"" + layer.id + "-object" + std::to_string(object) + "\" inkscape:label=\"" + name +
                        "\" data-object=\"" + name + "\">\n";
            }
            for (const Mark& m : layer.marks) {
                if (m.object != object) continue;
                marks.add(body, m);
            }
            if (by_object) body += "</g>\n";
        }
        body += "</g>\n";
    }
    return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
           "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" "
           "version=\"1.1\" width=\"" + W + "\" height=\"" + H + "\" viewBox=\"0 0 " + W + " " + H + "\">\n" +
           (marks.defs.empty() ? "" : "<defs>\n" + marks.defs + "</defs>\n") + "<rect id=\"background\" x=\"0\" y=\"0\" width=\"" +
           W + "\" height=\"" + H + "\" fill=\"" + hex_colour(sd.background) + "\"/>\n" +
           (sd.base.empty() ? std::string() : svg_raster_layer(sd.base)) + body + "</svg>\n";
}

}  // namespace

std::string styled_to_bytes(const StyledDrawing& sd, Format f) {
    if (f == Format::Json) throw Error("--style", "stylized output is drawn (svg, pdf, png); JSON keeps the exact pieces");
    if (f == Format::Svg) return styled_to_svg(sd);
    std::string bytes;
    const int w = sd.width, h = sd.height;
    SurfacePtr surface(f == Format::Pdf ? cairo_api().pdf_surface_create_for_stream(append, &bytes, w, h)
                                        : cairo_api().image_surface_create(CAIRO_FORMAT_RGB24, w, h),
                       cairo_api().surface_destroy);
    cairo_surface_t* s = surface.get();
    cairo_status_t st = cairo_api().surface_status(s);
    if (st == CAIRO_STATUS_SUCCESS) st = draw(s, sd, f != Format::Pdf || sd.background != 0xffffff, f == Format::Pdf);
    if (st == CAIRO_STATUS_SUCCESS && f == Format::Png) {
        st = cairo_api().surface_write_to_png_stream(s, append, &bytes);
    } else if (st == CAIRO_STATUS_SUCCESS) {
        cairo_api().surface_finish(s);
        st = cairo_api().surface_status(s);
    }
    if (st != CAIRO_STATUS_SUCCESS) throw Error("cairo", cairo_api().status_to_string(st));
    return bytes;
}

void styled_to_pixels(const StyledDrawing& sd, std::vector<std::uint32_t>& pixels) {
    const int w = sd.width, h = sd.height;
    pixels.assign(std::size_t(w) * std::size_t(h), 0xffffffffu);
    const int stride = cairo_api().format_stride_for_width(CAIRO_FORMAT_RGB24, w);
    if (stride != 4 * w) throw Error("cairo", "unexpected stride for a " + std::to_string(w) + " px wide image");
    SurfacePtr surface(cairo_api().image_surface_create_for_data(reinterpret_cast<unsigned char*>(pixels.data()),
                                                           CAIRO_FORMAT_RGB24, w, h, stride),
                       cairo_api().surface_destroy);
    cairo_status_t st = cairo_api().surface_status(surface.get());
    if (st == CAIRO_STATUS_SUCCESS) st = draw(surface.get(), sd, true);
    cairo_api().surface_flush(surface.get());
    if (st != CAIRO_STATUS_SUCCESS) throw Error("cairo", cairo_api().status_to_string(st));
}

void write_styled(const StyledDrawing& sd, const std::string& path, Format f) {
    std::string bytes;
    try {
        bytes = styled_to_bytes(sd, f);
    } catch (const Error& e) {
        throw Error(path, e.what());
    }
    write_text_file(path, bytes);
}

}  // namespace inkline
