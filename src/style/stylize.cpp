#include "style/stylize.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <glm/geometric.hpp>

#include "style/noise.hpp"
#include "style/offsets.hpp"
#include "style/strokes.hpp"

namespace inkline {

double base_width(const Style& s, int height) {
    return s.base_width > 0 ? s.base_width : std::max(1.0, 1.5 * height / 1024.0);
}

namespace {

// Liang-Barsky, as output/writers.cpp: the parts of a polyline inside the box [lo, hi]. Cairo's
// 24.8 fixed point wraps beyond about 8e6 px; projections near the eye plane reach that.
std::vector<std::vector<glm::dvec2>> clip_runs(const std::vector<glm::dvec2>& p, const glm::dvec2& lo,
                                               const glm::dvec2& hi) {
    std::vector<std::vector<glm::dvec2>> runs;
    bool open = false;
    for (std::size_t i = 1; i < p.size(); ++i) {
        glm::dvec2 a = p[i - 1], b = p[i];
        const glm::dvec2 d = b - a;
        double t0 = 0, t1 = 1;
        bool keep = true;
        for (int k = 0; k < 2 && keep; ++k) {
            const double pp[2] = {-d[k], d[k]}, q[2] = {a[k] - lo[k], hi[k] - a[k]};
            for (int m = 0; m < 2; ++m) {
                if (pp[m] == 0 && q[m] < 0) keep = false;
                if (pp[m] < 0) t0 = std::max(t0, q[m] / pp[m]);
                if (pp[m] > 0) t1 = std::min(t1, q[m] / pp[m]);
            }
        }
        if (!keep || !(t0 <= t1)) {
            open = false;
            continue;
        }
        const glm::dvec2 a0 = a;
        if (t0 > 0) a = a0 + t0 * d;
        if (t1 < 1) b = a0 + t1 * d;
        if (!open) runs.push_back({a});
        runs.back().push_back(b);
        open = b == p[i];
    }
    return runs;
}

glm::dvec2 normal_at(const std::vector<glm::dvec2>& p, std::size_t i) {
    glm::dvec2 t(0.0);
    if (i + 1 < p.size() && p[i + 1] != p[i]) t += glm::normalize(p[i + 1] - p[i]);
    if (i > 0 && p[i] != p[i - 1]) t += glm::normalize(p[i] - p[i - 1]);
    if (glm::length(t) < 1e-12) {  // a cusp (the path doubles back) or a single point
        for (std::size_t k = 1; k < p.size(); ++k)
            if (p[k] != p[k - 1]) { t = p[k] - p[k - 1]; break; }
        if (glm::length(t) < 1e-12) t = glm::dvec2(1, 0);
    }
    t = glm::normalize(t);
    return {-t.y, t.x};
}

class Builder {
public:
    Builder(const Style& s, int height) : style_(s), bw_(base_width(s, height)) {}
    double depth_lo = 0.0, depth_hi = 0.0;  // depth range of the drawing (width_by_depth)

    // depth, tone: per spine point, or null.
    // object: the stroke's object (scenes of several objects), kept apart in the marks.
    void add(const ArcPolyline& spine, const LineStyle& ls, StyledLayer& layer, StylizeStats& st,
             const std::vector<double>* depth = nullptr, const std::vector<double>* tone = nullptr,
             std::uint32_t object = 0) {
        if (ls.omit || spine.size() < 2) return;
        object_ = object;
        ++st.strokes;
        const double w = ls.width * bw_;
        if (ls.plain()) {
            Mark& m = mark(layer, Mark::Type::Stroke, ls, w);
            m.paths.push_back(spine.points());
            st.points += spine.size();
            return;
        }
        // Runs of displaced points with the spine arc length of each point.
        std::vector<OffsetRun> runs;
        if (ls.offsets) {
            runs = apply_offsets(spine, *ls.offsets, ls.offset_scale, ls.offset_period, ls.spacing);
        } else {
            OffsetRun r;
            r.points = spine.resample(ls.spacing);
            for (std::size_t i = 0; i < r.points.size(); ++i)
                r.arc.push_back(std::min(double(i) * ls.spacing, spine.length()));
            runs.push_back(std::move(r));
        }
        if (ls.noise.active())
            for (OffsetRun& r : runs)
                for (std::size_t i = 0; i < r.points.size(); ++i)
                    r.points[i] += noise_offset(noise_, r.points[i], spine.tangent(r.arc[i]), ls.noise.normal,
                                                ls.noise.tangent, ls.noise.wavelength);
        const double L = spine.length();
        // Attributes at arc length s: linear between the spine's points.
        const auto sample = [&](const std::vector<double>& v, double s) {
            const std::size_t i = spine.segment(s);
            const double a = spine.arc()[i], b = spine.arc()[std::min(i + 1, spine.size() - 1)];
            const double t = b > a ? std::clamp((s - a) / (b - a), 0.0, 1.0) : 0.0;
            return v[i] + t * (v[std::min(i + 1, v.size() - 1)] - v[i]);
        };
        const bool by_depth = depth && depth->size() == spine.size() && (ls.depth_near != 1 || ls.depth_far != 1);
        const bool by_light = tone && tone->size() == spine.size() && (ls.light_lit != 1 || ls.light_dark != 1);
        const auto width_at = [&](double s) {
            double k = 1.0;
            if (by_depth) {
                const double f = depth_hi > depth_lo ? std::clamp((sample(*depth, s) - depth_lo) / (depth_hi - depth_lo), 0.0, 1.0) : 0.0;
                k *= ls.depth_near + f * (ls.depth_far - ls.depth_near);
            }
            if (by_light) k *= ls.light_dark + sample(*tone, s) * (ls.light_lit - ls.light_dark);
            if (ls.width_rule != WidthRule::Taper || ls.taper_length <= 0) return w * k;
            const double f = std::clamp(std::min(s, L - s) / ls.taper_length, 0.0, 1.0);
            return w * k * (ls.taper_min + (1 - ls.taper_min) * std::sin(f * M_PI / 2));
        };
        const bool varying = by_depth || by_light || ls.width_rule == WidthRule::Taper;
        for (OffsetRun& r : runs) {
            if (r.points.size() < 2) continue;
            st.points += r.points.size();
            if (!ls.brush.empty()) {
                add_brush(mark(layer, Mark::Type::Brush, ls, w), r, width_at, ls);
            } else if (!varying) {
                mark(layer, Mark::Type::Stroke, ls, w).paths.push_back(std::move(r.points));
            } else {
                std::vector<double> widths;
                for (double s : r.arc) widths.push_back(width_at(s));
                mark(layer, Mark::Type::Fill, ls, w).paths.push_back(width_outline(r.points, widths));
            }
        }
    }

private:
    Mark& mark(StyledLayer& layer, Mark::Type type, const LineStyle& ls, double w) {
        for (Mark& m : layer.marks)
            if (m.type == type && m.rgb == ls.rgb && m.opacity == ls.opacity && m.width == w &&
                m.dash_on == ls.dash_on && m.dash_off == ls.dash_off && m.brush == ls.brush && m.object == object_)
                return m;
        Mark m;
        m.type = type;
        m.rgb = ls.rgb;
        m.opacity = ls.opacity;
        m.width = w;
        m.dash_on = ls.dash_on;
        m.dash_off = ls.dash_off;
        m.brush = ls.brush;
        m.object = object_;
        layer.marks.push_back(std::move(m));
        return layer.marks.back();
    }

    // Crossbars at every vertex and at every seam between repetitions of the brush image
    // (Markosian et al. 97, section 5); one quad between consecutive crossbars.
    template <class WidthAt>
    void add_brush(Mark& m, const OffsetRun& r, const WidthAt& width_at, const LineStyle& ls) {
        const double aspect = ls.brush_aspect > 0 ? ls.brush_aspect : 4.0;
        struct Bar { glm::dvec2 p, n; double s, w; };
        std::vector<Bar> bars;
        // Arc length along the displaced run (the texture follows what is drawn).
        double s = 0.0;
        for (std::size_t i = 0; i < r.points.size(); ++i) {
            const double w = width_at(r.arc[i]);
            if (i > 0) {
                const glm::dvec2 a = r.points[i - 1], b = r.points[i];
                const double len = glm::distance(a, b);
                const double seg_len = aspect * w;
                // Seams inside this segment (none where the stroke has no width).
                for (double k = std::floor(s / seg_len) + 1; seg_len > 1e-3 && k * seg_len < s + len; k += 1) {
                    const double f = (k * seg_len - s) / len;
                    const glm::dvec2 d = glm::normalize(b - a);
                    bars.push_back({a + f * (b - a), {-d.y, d.x}, k * seg_len, w});
                }
                s += len;
            }
            bars.push_back({r.points[i], normal_at(r.points, i), s, w});
        }
        for (std::size_t i = 1; i < bars.size(); ++i) {
            const Bar &a = bars[i - 1], &b = bars[i];
            if (b.s - a.s <= 1e-9) continue;
            const double seg_len = aspect * 0.5 * (a.w + b.w);
            if (!(seg_len > 1e-3)) continue;  // no width: nothing to draw
            BrushQuad q;
            q.corner[0] = a.p + 0.5 * a.w * a.n;
            q.corner[1] = a.p - 0.5 * a.w * a.n;
            q.corner[2] = b.p - 0.5 * b.w * b.n;
            q.corner[3] = b.p + 0.5 * b.w * b.n;
            const double k = std::floor(a.s / seg_len + 1e-9);
            q.u0 = a.s / seg_len - k;
            q.u1 = std::min(1.0, q.u0 + (b.s - a.s) / seg_len);
            m.quads.push_back(q);
        }
    }

    const Style& style_;
    double bw_;
    PerlinNoise noise_{0};
    std::uint32_t object_ = 0;  // add()'s object, for mark()
};

}  // namespace

// The mean opacity of a stroke's points (Piece::opacity; 1 where a piece has none), in steps of
// 1/8 so that a layer keeps few marks.
double stroke_opacity(const Drawing& d, const Stroke& s) {
    double sum = 0.0;
    std::size_t n = 0;
    for (std::uint32_t i : s.pieces)
        for (float o : d.pieces[i].opacity) sum += o, ++n;
    return n == 0 ? 1.0 : std::round(8.0 * sum / double(n)) / 8.0;
}

std::vector<glm::dvec2> width_outline(const std::vector<glm::dvec2>& p, const std::vector<double>& widths) {
    std::vector<glm::dvec2> out;
    if (p.size() < 2) return out;
    out.reserve(2 * p.size() + 1);
    for (std::size_t i = 0; i < p.size(); ++i) out.push_back(p[i] + 0.5 * widths[i] * normal_at(p, i));
    for (std::size_t i = p.size(); i-- > 0;) out.push_back(p[i] - 0.5 * widths[i] * normal_at(p, i));
    out.push_back(out.front());
    return out;
}

StyledDrawing stylize(const Drawing& d, const Style& style, bool hidden,
                      const std::vector<std::vector<glm::dvec2>>& hatches, StylizeStats* stats,
                      const PointAttributes* attributes) {
    StylizeStats st;
    StyledDrawing out;
    out.width = d.camera.width();
    out.height = d.camera.height();
    out.background = style.background;
    out.base = d.base;
    out.object_names = d.object_names;
    const bool draw_hidden = (hidden || style.draw_hidden) && !style.hidden.empty();
    ChainOptions co;
    co.hidden = draw_hidden;
    co.join = style.chain;
    co.max_turn_degrees = style.max_turn_degrees;
    co.join_distance = style.join_distance;
    co.keep_specks = style.keep_specks;
    ChainStats chain_stats;
    const std::vector<Stroke> strokes = chain_strokes(d, co, attributes, &chain_stats);
    st.specks_dropped = chain_stats.specks_dropped;
    const double margin = std::max(out.width, out.height);
    const glm::dvec2 lo(-margin, -margin), hi(out.width + margin, out.height + margin);
    Builder builder(style, out.height);
    bool first_depth = true;
    for (const Stroke& s : strokes)
        for (double z : s.depth) {
            builder.depth_lo = first_depth ? z : std::min(builder.depth_lo, z);
            builder.depth_hi = first_depth ? z : std::max(builder.depth_hi, z);
            first_depth = false;
        }

    // Layers as the default writers order them: deepest hidden level first, kinds in enum order,
    // then hatching, then visible lines.
    const int levels = draw_hidden ? int(style.hidden.size()) : 0;
    const auto layer_for = [&](int level, int kind) {
        StyledLayer layer;
        layer.id = std::string(to_string(LineKind(kind))) + "-" +
                   (level == 0 ? std::string("visible")
                               : "hidden-qi" + std::to_string(level) + (level == levels && levels > 1 ? "plus" : ""));
        for (const Stroke& s : strokes) {
            if (int(s.kind) != kind || std::min(s.qi, std::max(levels, 0)) != level || (s.qi > 0 && level == 0)) continue;
            const bool named = d.object_names.size() > 1 && s.object < d.object_names.size();
            LineStyle ls = style.for_line(s.kind, s.qi, named ? &d.object_names[s.object] : nullptr);
            ls.opacity *= stroke_opacity(d, s);  // tone lines carry an opacity per point
            if (!(ls.opacity > 0.0)) continue;
            auto runs = clip_runs(s.path.points(), lo, hi);
            // Attributes follow the points only when clipping left the stroke whole.
            const bool whole = runs.size() == 1 && runs[0].size() == s.path.size() && runs[0] == s.path.points();
            for (auto& run : runs)
                builder.add(ArcPolyline(std::move(run)), ls, layer, st, whole && !s.depth.empty() ? &s.depth : nullptr,
                            whole && !s.tone.empty() ? &s.tone : nullptr, s.object);
        }
        if (!layer.marks.empty()) out.layers.push_back(std::move(layer));
    };
    for (int level = levels; level >= 1; --level)
        for (int k = 0; k < kPieceKindCount; ++k) layer_for(level, k);
    if (!hatches.empty()) {
        StyledLayer layer;
        layer.id = "hatching";
        for (const auto& h : hatches)
            for (auto& run : clip_runs(h, lo, hi)) builder.add(ArcPolyline(std::move(run)), style.hatching.line, layer, st);
        st.hatches = hatches.size();
        if (!layer.marks.empty()) out.layers.push_back(std::move(layer));
    }
    for (int k = 0; k < kPieceKindCount; ++k) layer_for(0, k);
    if (stats) *stats = st;
    return out;
}

}  // namespace inkline
