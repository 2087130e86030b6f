// Stylization, step 1: visible (or hidden) pieces of a Drawing become long 2D strokes.
// Takes a Drawing (pieces with kind, QI, curve id, object, pixel polylines); gives Strokes: chains
// of pieces of one kind, one QI and one object joined end to end where an end of one piece lies on
// an end of another (pieces of the same curve always; across junctions only where the tangent
// turns by less than a small angle; specks, pieces shorter than a pixel, to any neighbour), never
// across gaps; a chain still shorter than a pixel is a speck alone and dropped unless kept.
// The default writers (output/) and the styles draw these same strokes. Strokes are
// parameterized by arc length (ArcPolyline) and can be resampled at a chosen spacing.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "core/drawing.hpp"

namespace inkline {

// A polyline with its cumulative arc length: s[0] = 0, s[i] = s[i-1] + |p[i] - p[i-1]|.
// Consecutive duplicate points are dropped on construction.
class ArcPolyline {
public:
    ArcPolyline() = default;
    explicit ArcPolyline(std::vector<glm::dvec2> points);

    const std::vector<glm::dvec2>& points() const { return p_; }
    const std::vector<double>& arc() const { return s_; }
    double length() const { return s_.empty() ? 0.0 : s_.back(); }
    std::size_t size() const { return p_.size(); }

    // Point at arc length s (clamped to [0, length]); linear between vertices.
    glm::dvec2 at(double s) const;
    // Unit tangent at arc length s: the direction of the segment holding s (at a vertex, the
    // average of the two segments' directions). (0, 0) for a polyline of fewer than 2 points.
    glm::dvec2 tangent(double s) const;
    // Index i of the segment [p[i], p[i+1]] holding arc length s.
    std::size_t segment(double s) const;
    // Points at arc lengths 0, d, 2d, ..., with the last point always kept (spacing d > 0; the
    // last interval may be shorter). Every original vertex is dropped unless it falls on a
    // sample: the result is uniform in arc length.
    std::vector<glm::dvec2> resample(double spacing) const;

private:
    std::vector<glm::dvec2> p_;
    std::vector<double> s_;
};

struct Stroke {
    LineKind kind = LineKind::Silhouette;
    int qi = 0;
    std::uint32_t object = 0;            // Piece::object
    bool closed = false;                 // the chain came back to its start (last point == first)
    std::vector<std::uint32_t> pieces;   // indices into Drawing::pieces, in stroke order
    ArcPolyline path;                    // pixels
    // Per point of `path`, when the pieces came with them (PointAttributes): camera depth and
    // Lambertian tone; empty otherwise.
    std::vector<double> depth, tone;
};

// Per piece of a Drawing, per point: camera depth and tone (see style/attributes.hpp); a piece's
// vectors are empty when unknown.
struct PointAttributes {
    std::vector<std::vector<double>> depth, tone;
};

struct ChainOptions {
    double join_distance = 1e-3;   // px: ends closer than this are the same point (no gaps jumped)
    double max_turn_degrees = 30;  // across a junction of different curves: largest tangent turn
    bool hidden = false;           // also chain hidden pieces (qi > 0)
    bool join = true;              // false: one stroke per piece
    // Pieces shorter than this (px) join a neighbour whatever the turn (after every other join);
    // strokes still shorter are specks, dropped unless keep_specks. One pixel: less is confetti
    // to whoever edits the drawing, and within the width of the line beside it.
    double speck_length = 1.0;
    bool keep_specks = false;
};

struct ChainStats {
    std::size_t specks_dropped = 0;  // pieces dropped in strokes shorter than speck_length
};

// Pieces with fewer than two points or a non-finite point are skipped (as the writers do).
// Strokes come in the order of their first piece's index.
std::vector<Stroke> chain_strokes(const Drawing& drawing, const ChainOptions& options = {},
                                  const PointAttributes* attributes = nullptr, ChainStats* stats = nullptr);

}  // namespace inkline
