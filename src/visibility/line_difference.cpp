#include "visibility/line_difference.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <map>

#include <glm/geometric.hpp>

namespace inkline {

long SegmentProximity::cell(double v) const { return long(std::floor(v / cell_)); }

void SegmentProximity::add(const std::vector<glm::dvec2>& p) {
    for (std::size_t i = 1; i < p.size(); ++i) segments_.push_back({p[i - 1], p[i]});
}

void SegmentProximity::build() {
    if (segments_.empty()) return;
    long xa = LONG_MAX, ya = LONG_MAX, xb = LONG_MIN, yb = LONG_MIN;
    for (const auto& [a, b] : segments_) {
        xa = std::min(xa, cell(std::min(a.x, b.x))), xb = std::max(xb, cell(std::max(a.x, b.x)));
        ya = std::min(ya, cell(std::min(a.y, b.y))), yb = std::max(yb, cell(std::max(a.y, b.y)));
    }
    // (lines far beyond the image, e.g. near the eye, would make the grid huge: coarser cells)
    while (double(xb - xa + 1) * double(yb - ya + 1) > 4e6) {
        cell_ *= 2.0;
        xa = ya = LONG_MAX, xb = yb = LONG_MIN;
        for (const auto& [a, b] : segments_) {
            xa = std::min(xa, cell(std::min(a.x, b.x))), xb = std::max(xb, cell(std::max(a.x, b.x)));
            ya = std::min(ya, cell(std::min(a.y, b.y))), yb = std::max(yb, cell(std::max(a.y, b.y)));
        }
    }
    x0_ = xa, y0_ = ya, nx_ = xb - xa + 1, ny_ = yb - ya + 1;
    begin_.assign(std::size_t(nx_ * ny_) + 1, 0);
    // Two passes over the segments' boxes: count per cell, then fill (a segment's box of cells).
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<std::uint32_t> fill;
        if (pass == 1) {
            for (std::size_t k = 1; k < begin_.size(); ++k) begin_[k] += begin_[k - 1];
            ids_.resize(begin_.back());
            fill.assign(begin_.begin(), begin_.end() - 1);
        }
        for (std::uint32_t id = 0; id < segments_.size(); ++id) {
            const auto& [a, b] = segments_[id];
            for (long cy = cell(std::min(a.y, b.y)); cy <= cell(std::max(a.y, b.y)); ++cy)
                for (long cx = cell(std::min(a.x, b.x)); cx <= cell(std::max(a.x, b.x)); ++cx) {
                    const std::size_t c = std::size_t((cy - y0_) * nx_ + (cx - x0_));
                    if (pass == 0) ++begin_[c + 1];
                    else ids_[fill[c]++] = id;
                }
        }
    }
}

bool SegmentProximity::within(glm::dvec2 q, double limit) const {
    if (segments_.empty() || begin_.empty()) return false;
    const long xa = std::max(cell(q.x - limit), x0_), xb = std::min(cell(q.x + limit), x0_ + nx_ - 1);
    const long ya = std::max(cell(q.y - limit), y0_), yb = std::min(cell(q.y + limit), y0_ + ny_ - 1);
    for (long cy = ya; cy <= yb; ++cy)
        for (long cx = xa; cx <= xb; ++cx) {
            const std::size_t c = std::size_t((cy - y0_) * nx_ + (cx - x0_));
            for (std::uint32_t k = begin_[c]; k < begin_[c + 1]; ++k) {
                const auto& [a, b] = segments_[ids_[k]];
                const glm::dvec2 ab = b - a;
                const double l2 = glm::dot(ab, ab);
                const double t = l2 > 0.0 ? std::clamp(glm::dot(q - a, ab) / l2, 0.0, 1.0) : 0.0;
                if (glm::distance(q, a + t * ab) <= limit) return true;
            }
        }
    return false;
}

std::pair<double, double> length_near(const std::vector<std::vector<glm::dvec2>>& from, const SegmentProximity& to,
                                      double limit) {
    double total = 0.0, near = 0.0;
    for (const auto& p : from)
        for (std::size_t i = 1; i < p.size(); ++i) {
            const double len = glm::distance(p[i - 1], p[i]);
            // (a quarter pixel apart, up to 4096 points: lines near the eye can project far
            // beyond the image)
            const int n = std::clamp(int(std::min(std::ceil(len / 0.25), 4096.0)), 1, 4096);
            for (int k = 0; k < n; ++k) {
                const glm::dvec2 q = p[i - 1] + (k + 0.5) / n * (p[i] - p[i - 1]);
                total += len / n;
                if (to.within(q, limit)) near += len / n;
            }
        }
    return {total, near};
}

namespace {
std::vector<std::vector<glm::dvec2>> visible_lines(const Drawing& d) {
    std::vector<std::vector<glm::dvec2>> out;
    for (const Piece& p : d.pieces)
        if (p.qi == 0) out.push_back(p.points);
    return out;
}
}  // namespace

LineDifference visible_difference(const Drawing& reference, const Drawing& other, double tolerance_px) {
    const auto ref = visible_lines(reference), oth = visible_lines(other);
    SegmentProximity ref_index, oth_index;
    for (const auto& p : ref) ref_index.add(p);
    for (const auto& p : oth) oth_index.add(p);
    ref_index.build(), oth_index.build();
    LineDifference d;
    const auto [rt, rn] = length_near(ref, oth_index, tolerance_px);
    const auto [ot, on] = length_near(oth, ref_index, tolerance_px);
    d.reference_px = rt, d.missing_px = rt - rn;
    d.other_px = ot, d.extra_px = ot - on;
    return d;
}

namespace {
// Pieces' polylines by class: (kind, QI or visible/hidden).
using LineClasses = std::map<std::pair<int, int>, std::vector<std::vector<glm::dvec2>>>;
LineClasses lines_by_class(const Drawing& d, bool qi_levels) {
    LineClasses out;
    for (const Piece& p : d.pieces) out[{int(p.kind), qi_levels ? p.qi : int(p.qi > 0)}].push_back(p.points);
    return out;
}
}  // namespace

std::vector<ClassDifference> drawing_difference_by_class(const Drawing& reference, const Drawing& other,
                                                         double tolerance_px, bool qi_levels) {
    LineClasses ref = lines_by_class(reference, qi_levels), oth = lines_by_class(other, qi_levels);
    for (const auto& [key, lines] : ref) oth[key];  // (a class of one drawing only: all of it differs)
    for (const auto& [key, lines] : oth) ref[key];
    std::vector<ClassDifference> out;
    for (const auto& [key, ref_lines] : ref) {
        const auto& oth_lines = oth.at(key);
        SegmentProximity ref_index, oth_index;
        for (const auto& p : ref_lines) ref_index.add(p);
        for (const auto& p : oth_lines) oth_index.add(p);
        ref_index.build(), oth_index.build();
        const auto [rt, rn] = length_near(ref_lines, oth_index, tolerance_px);
        const auto [ot, on] = length_near(oth_lines, ref_index, tolerance_px);
        ClassDifference c{LineKind(key.first), key.second, {}};
        c.difference.reference_px = rt, c.difference.missing_px = rt - rn;
        c.difference.other_px = ot, c.difference.extra_px = ot - on;
        out.push_back(c);
    }
    return out;
}

LineDifference drawing_difference(const Drawing& reference, const Drawing& other, double tolerance_px,
                                  bool qi_levels) {
    LineDifference d;
    for (const ClassDifference& c : drawing_difference_by_class(reference, other, tolerance_px, qi_levels)) {
        d.reference_px += c.difference.reference_px, d.missing_px += c.difference.missing_px;
        d.other_px += c.difference.other_px, d.extra_px += c.difference.extra_px;
    }
    return d;
}

}  // namespace inkline
