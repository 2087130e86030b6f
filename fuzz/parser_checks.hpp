// The parser fuzzers' checks (fuzz_offsets, fuzz_style, fuzz_bpt, fuzz_surfaces), shared with the
// regression tests (tests/test_fuzz_regressions.cpp replays fuzz/regressions/<target>-*): each
// parses its input the way inkline does and pushes an accepted result a little way down the
// pipeline at small, fixed sizes. inkline::Error is the expected answer to bad input. Returns ""
// when the input was refused or went through cleanly, else what is wrong (a non-finite point, an
// output out of all proportion to the input); a crash, a sanitizer report, another exception or a
// hang is a finding too (the fuzzer reports those itself).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "core/error.hpp"
#include "freeform/strokes.hpp"
#include "freeform/surface.hpp"
#include "freeform/tessellate.hpp"
#include "style/offsets.hpp"
#include "style/strokes.hpp"
#include "style/style.hpp"
#include "style/stylize.hpp"

namespace inkline_fuzz {

inline bool finite2(glm::dvec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }
inline bool finite3(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// Offset table: parsed, then applied along a 150 px spine with the extremes a style may ask for
// (scale +-100; the table's period or the shortest override the style parser allows: 0.1 px, and
// no more than 100 table vertices per px; spacing 0.05 px: styles/README.md).
inline std::string check_offsets(const std::string& text) {
    inkline::OffsetTable t;
    try {
        t = inkline::parse_offset_table(text, "fuzz.txt");
    } catch (const inkline::Error&) {
        return "";
    }
    const inkline::ArcPolyline spine({{0, 0}, {60, 0}, {60, 40}, {20, 70}});
    for (double scale : {1.0, -100.0, 100.0})
        for (double period : {0.0, std::max(0.1, double(t.vertices.size()) / inkline::kMaxOffsetVerticesPerPx),
                              std::max(7.5, double(t.vertices.size()) / inkline::kMaxOffsetVerticesPerPx)})
            for (double spacing : {1.5, 0.05}) {
                const auto runs = inkline::apply_offsets(spine, t, scale, period, spacing);
                std::size_t n = 0;
                for (const auto& r : runs) {
                    n += r.points.size();
                    if (r.points.size() != r.arc.size()) return "a run's points and arc lengths differ in count";
                    for (const auto& p : r.points)
                        if (!finite2(p)) return "non-finite offset point";
                    for (double s : r.arc)
                        if (!(s >= 0 && s <= spine.length())) return "arc length outside the spine";
                }
                // 150 px at 0.05 px spacing is 3000 points; table vertices add a bounded number per px.
                if (n > 2000000) return "offsets give " + std::to_string(n) + " points along a 150 px stroke";
            }
    return "";
}

// A small drawing with every line kind, visible and hidden at several QI levels (closed loops, a
// zigzag, a two-point piece, a piece with repeated points).
inline inkline::Drawing sample_drawing() {
    inkline::Drawing d;
    d.camera = inkline::Camera::perspective({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40, 96, 64);
    std::uint32_t curve = 0;
    for (int k = 0; k < inkline::kPieceKindCount; ++k)
        for (int qi : {0, 1, 3}) {
            inkline::Piece p;
            p.kind = inkline::LineKind(k);
            p.qi = qi;
            p.curve = curve++;
            const double x = 8 + 20 * k, y = 8 + 18 * qi;
            p.points = {{x, y}, {x + 15, y}, {x + 15, y + 12}, {x + 3, y + 14}, {x, y}};
            d.pieces.push_back(p);
            p.curve = curve++;
            p.points = {{x, y + 2}, {x + 2, y + 6}, {x + 2, y + 6}, {x + 4, y + 2}, {x + 6, y + 6}};
            d.pieces.push_back(p);
            p.curve = curve++;
            p.points = {{x + 1, y + 1}, {x + 1.5, y + 1}};
            d.pieces.push_back(p);
        }
    return d;
}

// Style file: parsed (relative offset tables and brushes resolved against `styles_dir`, the
// repository's styles/), then the sample drawing stylized with hidden lines and two hatches.
inline std::string check_style(const std::string& text, const std::string& styles_dir) {
    inkline::Style s;
    try {
        s = inkline::parse_style(text, styles_dir + "/fuzz.json");
    } catch (const inkline::Error&) {
        return "";
    }
    const std::vector<std::vector<glm::dvec2>> hatches{{{10, 10}, {30, 20}, {31, 20}}, {{50, 50}, {50, 50.5}}};
    for (bool hidden : {false, true}) {
        const inkline::StyledDrawing sd = inkline::stylize(sample_drawing(), s, hidden, hatches);
        std::size_t n = 0;
        for (const auto& layer : sd.layers)
            for (const auto& m : layer.marks) {
                if (!std::isfinite(m.width) || !(m.width >= 0)) return "mark with a bad width";
                for (const auto& path : m.paths) {
                    n += path.size();
                    for (const auto& p : path)
                        if (!finite2(p)) return "non-finite point in layer " + layer.id;
                }
                for (const auto& q : m.quads) {
                    n += 4;
                    for (const auto& p : q.corner)
                        if (!finite2(p)) return "non-finite brush quad in layer " + layer.id;
                }
            }
        // About 1000 px of lines: at the finest spacing (0.05 px) and the shortest offset period,
        // a few hundred thousand points; more means some setting multiplies without bound.
        if (n > 5000000) return "stylizing gives " + std::to_string(n) + " points";
    }
    return "";
}

// Surfaces (.bpt or JSON): each surface evaluated with curvature on a 5 x 5 grid of its domain, a
// few short strokes grown on it, then all tessellated at low resolution (the mesh the pipeline
// gets). NaN may come out of curvature only where it says `valid = false`.
inline std::string check_surfaces(inkline::freeform::SurfaceList surfaces) {
    using namespace inkline::freeform;
    for (std::size_t k = 0; k < surfaces.size(); ++k) {
        const Surface& s = *surfaces[k];
        if (!(s.u_range[1] > s.u_range[0]) || !(s.v_range[1] > s.v_range[0]) || !finite2(s.u_range) ||
            !finite2(s.v_range))
            return "surface " + std::to_string(k) + " has an empty or non-finite domain";
        for (int i = 0; i <= 4; ++i)
            for (int j = 0; j <= 4; ++j) {
                const double u = s.u_range[0] + (s.u_range[1] - s.u_range[0]) * i / 4;
                const double v = s.v_range[0] + (s.v_range[1] - s.v_range[0]) * j / 4;
                const SurfacePoint p = s.eval(u, v);
                const Curvature c = curvature_of(p, 1.0);
                if (c.valid && finite3(p.p) && finite3(p.su) && finite3(p.sv) && finite3(p.suu) && finite3(p.suv) &&
                    finite3(p.svv) && !(finite3(c.n) && finite3(c.d1) && finite3(c.d2) && finite2(c.uv1) && finite2(c.uv2)))
                    return "valid curvature with non-finite values on surface " + std::to_string(k);
            }
    }
    StrokeOptions so;
    so.length = 0.5;
    so.min_step_fraction = 1.0 / 16;
    for (StrokeField f : {StrokeField::Iso, StrokeField::Curvature, StrokeField::Isophote}) {
        so.field = f;
        for (const auto& st : grow_strokes(surfaces, cover(surfaces, 6, 1, 4), so)) {
            if (st.points.size() > 10000) return "a stroke of " + std::to_string(st.points.size()) + " points";
            if (st.points.size() != st.uv.size() || st.points.size() != st.arc.size() || st.seed_at >= st.points.size())
                return "stroke arrays disagree";
        }
    }
    try {
        const Tessellation t = tessellate(surfaces, {2, 8}, "fuzz");
        for (const auto& p : t.mesh.positions)
            if (!finite3(p)) return "non-finite tessellation vertex";
        for (const auto& tr : t.mesh.triangles)
            for (auto i : tr)
                if (i >= t.mesh.positions.size()) return "tessellation index out of range";
    } catch (const inkline::Error&) {
    }
    return "";
}

inline std::string check_bpt(const std::string& text) {
    inkline::freeform::SurfaceList s;
    try {
        s = inkline::freeform::parse_bpt(text, "fuzz.bpt");
    } catch (const inkline::Error&) {
        return "";
    }
    return check_surfaces(std::move(s));
}

inline std::string check_surfaces_json(const std::string& text) {
    inkline::freeform::SurfaceList s;
    try {
        s = inkline::freeform::parse_surfaces_json(text, "fuzz.json");
    } catch (const inkline::Error&) {
        return "";
    }
    return check_surfaces(std::move(s));
}

}  // namespace inkline_fuzz
