// How far one drawing's visible lines are from another's (issue 46's error of the fast
// visibility): the visible length of each drawing farther than a tolerance from every visible
// line of the other. Takes two Drawings of the same view; gives lengths in pixels.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "core/drawing.hpp"

namespace inkline {

struct LineDifference {
    double reference_px = 0.0;  // visible length of the reference drawing
    double other_px = 0.0;      // visible length of the other drawing
    double missing_px = 0.0;    // of the reference's, farther than the tolerance from the other's
    double extra_px = 0.0;      // of the other's, farther than the tolerance from the reference's
    // (missing + extra) as a share of the reference's visible length (0 when it has none).
    double share() const { return reference_px > 0.0 ? (missing_px + extra_px) / reference_px : 0.0; }
};

// Segments of polylines binned in a uniform grid: is a point within a distance of any of them?
class SegmentProximity {
public:
    // `cell_px`: the grid's cell size (a query looks at the cells within its limit).
    explicit SegmentProximity(double cell_px = 2.0) : cell_(cell_px) {}
    void add(const std::vector<glm::dvec2>& polyline);
    void build();  // after the last add, before the first query
    bool within(glm::dvec2 q, double limit) const;

private:
    long cell(double v) const;
    double cell_;
    std::vector<std::pair<glm::dvec2, glm::dvec2>> segments_;
    long x0_ = 0, y0_ = 0, nx_ = 0, ny_ = 0;
    std::vector<std::uint32_t> begin_, ids_;  // per cell (row-major), the segments touching it
};

// Length (pixels) of `from`'s polylines within `limit` of `to`'s, measured at points a quarter
// pixel apart (at most 4096 points a segment): {total, near}.
std::pair<double, double> length_near(const std::vector<std::vector<glm::dvec2>>& from, const SegmentProximity& to,
                                      double limit);

// The visible (QI 0) pieces of `reference` and `other` against each other, within `tolerance_px`.
LineDifference visible_difference(const Drawing& reference, const Drawing& other, double tolerance_px = 1.0);

// Every piece of both drawings, visible and hidden, each compared only with the other drawing's
// pieces of its class: the same line kind and the same QI (with qi_levels false: both visible or
// both hidden, for views whose hidden QI is only a lower bound). Lengths of all pieces. It does
// not look at how lines are cut into pieces, their direction or their curves' numbers, so two
// drawings of one mesh numbered differently (another vertex and face order) can be compared:
// with a tolerance of rounding (e.g. 1e-6 px) it is zero when they draw the same lines.
LineDifference drawing_difference(const Drawing& reference, const Drawing& other, double tolerance_px,
                                  bool qi_levels = true);

// The same, per class (to see where two drawings differ).
struct ClassDifference {
    LineKind kind;
    int qi;  // with qi_levels false: 0 visible, 1 hidden
    LineDifference difference;
};
std::vector<ClassDifference> drawing_difference_by_class(const Drawing& reference, const Drawing& other,
                                                         double tolerance_px, bool qi_levels = true);

}  // namespace inkline
