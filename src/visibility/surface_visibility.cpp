#include "visibility/surface_visibility.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "model/orientation.hpp"
#include "visibility/appel.hpp"

namespace inkline {

namespace {

constexpr std::uint32_t kNoVertex = UINT32_MAX;

// The occluding edges (silhouettes and borders) in the image, clipped at the near plane.
void project_occluders(const MeshTopology& mesh, const Features& features, const Camera& camera,
                       std::vector<Segment2>& out) {
    out.clear();
    const double near = camera.near_distance();
    auto add = [&](std::uint32_t e) {
        const auto [v0, v1] = mesh.edge_vertex[e];
        glm::dvec3 A = mesh.positions[v0], B = mesh.positions[v1];
        const double dA = camera.depth(A) - near, dB = camera.depth(B) - near;
        if (!(dA > 0.0) && !(dB > 0.0)) return;
        if (!(dA > 0.0)) A += (B - A) * (dA / (dA - dB));
        if (!(dB > 0.0)) B += (A - B) * (dB / (dB - dA));
        out.push_back({camera.project(A), camera.project(B), v0, v1, e, 0.0});
    };
    for (std::uint32_t e : features.silhouette_edges) add(e);
    for (std::uint32_t e : features.border_edges) add(e);
}

// Faces a curve may pass between without a new ray test: the same face, or two across an edge.
bool joined(const MeshTopology& mesh, std::uint32_t fa, std::uint32_t fb) {
    if (fa == fb) return true;
    for (std::uint32_t g : mesh.face_edges[fa].face)
        if (g == fb) return true;
    return false;
}

// Both faces of consecutive segments joined (intersection curves: the second face on the other
// surface; kNoFace for surface curves, joined to itself).
bool joined(const MeshTopology& mesh, const SurfaceVisibilityScratch::RunSegment& last, std::uint32_t face,
            std::uint32_t face2) {
    return joined(mesh, last.face, face) && joined(mesh, last.face2, face2);
}

// Where along 3D segment A->B (s in [0, 1]) the image parameter t lies: the image of a point
// moving linearly in 3D moves with perspective foreshortening.
double segment_param(const Camera& camera, const glm::dvec3& A, const glm::dvec3& B, double t) {
    if (camera.is_ortho()) return t;
    const double zA = camera.depth(A), zB = camera.depth(B);
    const double den = (1.0 - t) * zB + t * zA;
    return den > 0.0 ? std::clamp(t * zA / den, 0.0, 1.0) : t;
}

// One run of a curve: consecutive segments in front of the near plane. Cuts it at its crossings,
// gives the pieces their QI and appends them.
class RunPieces {
public:
    RunPieces(const MeshTopology& mesh, const FaceFacing& face_front, const Camera& camera,
              const std::function<const RayCaster&()>& rays, const SurfaceVisibilityOptions& options,
              SurfaceVisibilityScratch& s, SurfaceVisibilityStats& st, std::vector<Piece>& out)
        : mesh_(mesh), face_front_(face_front), camera_(camera), rays_(rays), opt_(options), s_(s), st_(st),
          out_(out) {}

    // `reference`: a ray test per piece (the curve may change QI where the image shows nothing).
    void process(LineKind kind, std::uint32_t curve, bool closed, bool reference) {
        if (s_.run.empty()) return;
        find_crossings(closed);
        const std::size_t n_pieces = closed ? std::max<std::size_t>(s_.crossings.size(), 1) : s_.crossings.size() + 1;
        const std::size_t first = out_.size();
        for (std::size_t k = 0; k < n_pieces; ++k) {
            Piece p;
            p.kind = kind;
            p.curve = curve + opt_.curve_offset;
            piece_points(k, closed, p.points);
            out_.push_back(std::move(p));
        }
        assign_qi(first, closed, reference);
        // Pieces of no length (a crossing at a curve's end) are dropped after their QI passed on.
        std::size_t w = first;
        for (std::size_t i = first; i < out_.size(); ++i)
            if (has_length(out_[i].points)) {
                if (w != i) out_[w] = std::move(out_[i]);
                ++w;
            }
        out_.resize(w);
        st_.pieces += w - first;
    }

private:
    static bool has_length(const std::vector<glm::dvec2>& pts) {
        for (std::size_t i = 1; i < pts.size(); ++i)
            if (pts[i] != pts[0]) return true;
        return false;
    }

    // Every crossing of the run's image with an occluder's, in travel order. A crossing at a
    // segment's end is kept once (as the next segment's start), and an occluder that is an edge of
    // the segment's own face (either of an intersection curve's two) cannot hide it (they are in
    // one plane), so it is skipped.
    void find_crossings(bool closed) {
        auto& xs = s_.crossings;
        xs.clear();
        const std::size_t n = s_.run.size();
        for (std::size_t j = 0; j < n; ++j) {
            const auto& seg = s_.run[j];
            const Segment2 q{seg.a, seg.b, kNoVertex, kNoVertex, kNoVertex, 0.0};
            const auto& own = mesh_.face_edges[seg.face].edge;
            static constexpr std::array<std::uint32_t, 3> kNone{kNoVertex, kNoVertex, kNoVertex};
            const auto& own2 = seg.face2 == kNoFace ? kNone : mesh_.face_edges[seg.face2].edge;
            s_.grid.candidates(q, [&](std::uint32_t k) {
                const Segment2& o = s_.occluders[k];
                if (o.edge == own[0] || o.edge == own[1] || o.edge == own[2]) return;
                if (o.edge == own2[0] || o.edge == own2[1] || o.edge == own2[2]) return;
                double t[2];
                if (segment_crossings(q, o, t) != 1) return;  // (collinear images: not generic)
                if (t[0] >= 1.0 && (closed || j + 1 < n)) return;
                xs.push_back({std::uint32_t(j), t[0], o.edge, 0});
            });
            if (j > 0 || closed) {
                const auto& last = s_.run[j > 0 ? j - 1 : n - 1];
                add_fold(last.face, seg.face, std::uint32_t(j));
                if (seg.face2 != kNoFace) add_fold(last.face2, seg.face2, std::uint32_t(j));
            }
        }
        std::sort(xs.begin(), xs.end(), [](const auto& x, const auto& y) {
            return x.seg != y.seg ? x.seg < y.seg : x.t < y.t;
        });
        st_.crossings += xs.size();
    }

    // Where the curve passes from face fa to its neighbour fb over an edge where their facing
    // differs (a silhouette edge: the two faces fold onto one side of its image), the point goes
    // behind the sheet it leaves or comes out from behind the one it reaches. At a convex edge
    // the front face hides the back face near the edge; at a concave one the back face hides the
    // front face.
    void add_fold(std::uint32_t fa, std::uint32_t fb, std::uint32_t seg) {
        if (fa == fb) return;
        std::uint32_t shared = kNoVertex;
        for (std::uint32_t e : mesh_.face_edges[fa].edge)
            for (std::uint32_t g : mesh_.face_edges[fb].edge)
                if (e == g) shared = e;
        if (shared == kNoVertex) return;  // (not neighbours: a cut run never joins here)
        // (Facing relative to the shared edge's first face: convexity is, and on an orientation
        // seam the second face's winding is the other one.)
        const bool front_a = facing_relative_to_first(mesh_, shared, fa, face_front_[fa]);
        const bool front_b = facing_relative_to_first(mesh_, shared, fb, face_front_[fb]);
        if (front_a == front_b) return;
        const int into_hidden = mesh_.is_convex(shared) ? 1 : -1;
        s_.crossings.push_back({seg, 0.0, shared, front_a ? into_hidden : -into_hidden});
    }

    glm::dvec2 image_at(std::uint32_t seg, double t) const {
        const auto& r = s_.run[seg];
        return t <= 0.0 ? r.a : t >= 1.0 ? r.b : r.a + t * (r.b - r.a);
    }

    // Where piece k starts and ends (segment, image parameter). Open runs: from the run's start to
    // the first crossing, between crossings, from the last to the end. Closed: crossing k to k+1,
    // the last wrapping around; with no crossing, the whole loop.
    struct Bound {
        std::uint32_t seg;
        double t;
    };
    std::pair<Bound, Bound> bounds(std::size_t k, bool closed) const {
        const auto& xs = s_.crossings;
        const std::uint32_t last = std::uint32_t(s_.run.size() - 1);
        if (closed) {
            if (xs.empty()) return {{0, 0.0}, {last, 1.0}};
            const auto& a = xs[k];
            const auto& b = xs[(k + 1) % xs.size()];
            return {{a.seg, a.t}, {b.seg, b.t}};
        }
        const Bound start = k == 0 ? Bound{0, 0.0} : Bound{xs[k - 1].seg, xs[k - 1].t};
        const Bound end = k == xs.size() ? Bound{last, 1.0} : Bound{xs[k].seg, xs[k].t};
        return {start, end};
    }

    // Calls fn(seg, t0, t1) for each stretch of piece k within one segment, in travel order.
    template <class Fn>
    void for_stretches(std::size_t k, bool closed, Fn&& fn) const {
        const auto [a, b] = bounds(k, closed);
        const std::uint32_t n = std::uint32_t(s_.run.size());
        const bool wraps = closed && (b.seg < a.seg || (b.seg == a.seg && b.t <= a.t));
        std::uint32_t seg = a.seg;
        double t0 = a.t;
        for (std::uint32_t steps = 0; steps <= n; ++steps) {
            const bool final_seg = seg == b.seg && (!wraps || steps > 0);
            const double t1 = final_seg ? b.t : 1.0;
            fn(seg, t0, t1);
            if (final_seg) return;
            seg = (seg + 1) % n;
            t0 = 0.0;
        }
    }

    void piece_points(std::size_t k, bool closed, std::vector<glm::dvec2>& pts) const {
        bool first = true;
        for_stretches(k, closed, [&](std::uint32_t seg, double t0, double t1) {
            if (first) pts.push_back(image_at(seg, t0)), first = false;
            pts.push_back(image_at(seg, t1));
        });
    }

    // QI of piece k by a ray test at the middle of its longest stretch (inside that segment's face).
    int ray_qi(std::size_t k, bool closed) {
        double best = -1.0;
        std::uint32_t best_seg = 0;
        double b0 = 0.0, b1 = 1.0;
        for_stretches(k, closed, [&](std::uint32_t seg, double t0, double t1) {
            const double len = glm::length(image_at(seg, t1) - image_at(seg, t0));
            if (len > best) best = len, best_seg = seg, b0 = t0, b1 = t1;
        });
        const auto& r = s_.run[best_seg];
        const double s = 0.5 * (segment_param(camera_, r.A, r.B, b0) + segment_param(camera_, r.A, r.B, b1));
        const glm::dvec3 P = r.A + s * (r.B - r.A);
        ++st_.ray_tests;
        return rays_().count_layers(camera_.ray_origin(P), P, r.face, r.face2);
    }

    bool on_pierced_face() const {
        if (!opt_.pierced_faces) return false;
        for (const auto& r : s_.run)
            if ((*opt_.pierced_faces)[r.face]) return true;
        return false;
    }

    // Change of QI across crossing x (from the piece before it to the piece after it).
    int delta(const SurfaceVisibilityScratch::Crossing& x) const {
        if (x.fold != 0) return x.fold;
        const auto& r = s_.run[x.seg];
        return crossing_delta(mesh_, camera_, x.edge, r.A, r.B);
    }

    void assign_qi(std::size_t first, bool closed, bool reference) {
        const std::size_t n = out_.size() - first;
        if (!opt_.propagate || n == 1 || reference || on_pierced_face()) {
            if (opt_.propagate && n > 1) ++st_.fallbacks;
            for (std::size_t k = 0; k < n; ++k) out_[first + k].qi = ray_qi(k, closed);
            return;
        }
        // The base: the longest piece (its ray test is the least likely to graze anything).
        std::size_t base = 0;
        double best = -1.0;
        for (std::size_t k = 0; k < n; ++k) {
            const auto& pts = out_[first + k].points;
            double len = 0.0;
            for (std::size_t i = 1; i < pts.size(); ++i) len += glm::length(pts[i] - pts[i - 1]);
            if (len > best) best = len, base = k;
        }
        // Crossing between piece k and k + 1: open runs, crossing k; closed, crossing k + 1.
        auto between = [&](std::size_t k) -> const auto& {
            return s_.crossings[closed ? (k + 1) % s_.crossings.size() : k];
        };
        auto qi = [&](std::size_t k) -> int& { return out_[first + k].qi; };
        qi(base) = ray_qi(base, closed);
        bool consistent = true;
        for (std::size_t k = base + 1; k < n; ++k) consistent &= (qi(k) = qi(k - 1) + delta(between(k - 1))) >= 0;
        for (std::size_t k = base; k-- > 0;) consistent &= (qi(k) = qi(k + 1) - delta(between(k))) >= 0;
        // A closed loop must come back to its start.
        if (closed && consistent) consistent = qi(n - 1) + delta(between(n - 1)) == qi(0);
        if (!consistent) {
            ++st_.fallbacks;
            for (std::size_t k = 0; k < n; ++k) qi(k) = ray_qi(k, closed);
        }
    }

    const MeshTopology& mesh_;
    const FaceFacing& face_front_;
    const Camera& camera_;
    const std::function<const RayCaster&()>& rays_;
    const SurfaceVisibilityOptions& opt_;
    SurfaceVisibilityScratch& s_;
    SurfaceVisibilityStats& st_;
    std::vector<Piece>& out_;
};

// A curve as the run loop reads it; Source gives curve(c), point(i) and faces(i).
struct CurveInfo {
    LineKind kind;
    std::uint32_t begin, end;
    bool closed;
    bool reference;  // a ray test per piece
};
// (Sources also give cut(i): the QI may change at point i with no event in the image.)

struct SurfaceSource {
    const SurfaceCurves& c;
    std::size_t size() const { return c.curves.size(); }
    CurveInfo curve(std::size_t k) const {
        const auto& x = c.curves[k];
        return {x.kind, x.begin, x.end, x.closed, false};
    }
    const glm::dvec3& point(std::uint32_t i) const { return c.points[i]; }
    std::array<std::uint32_t, 2> faces(std::uint32_t i) const { return {c.segment_face[i], kNoFace}; }
    bool cut(std::uint32_t) const { return false; }
};

struct IntersectionSource {
    const IntersectionCurves& c;
    std::size_t size() const { return c.curves.size(); }
    CurveInfo curve(std::size_t k) const {
        const auto& x = c.curves[k];
        return {LineKind::Intersection, x.begin, x.end, x.closed, x.reference};
    }
    const glm::dvec3& point(std::uint32_t i) const { return c.points[i]; }
    std::array<std::uint32_t, 2> faces(std::uint32_t i) const { return c.segment_faces[i]; }
    bool cut(std::uint32_t i) const { return c.point_cut[i] != 0; }
};

// Each curve clipped at the near plane and cut into runs (RunPieces) where it leaves the view or
// jumps between faces that share no edge.
template <class Source>
SurfaceVisibilityStats visit_curves(const MeshTopology& mesh, const Features& features, const Camera& camera,
                                    const Source& curves, const std::function<const RayCaster&()>& rays,
                                    const SurfaceVisibilityOptions& options, SurfaceVisibilityScratch& s,
                                    std::vector<Piece>& out) {
    SurfaceVisibilityStats st;
    if (curves.size() == 0) return st;
    project_occluders(mesh, features, camera, s.occluders);
    s.grid.build(s.occluders, camera.width(), camera.height());
    RunPieces runs(mesh, features.face_front, camera, rays, options, s, st, out);
    const double near = camera.near_distance();
    for (std::uint32_t c = 0; c < curves.size(); ++c) {
        const CurveInfo curve = curves.curve(c);
        auto end_run = [&] {
            runs.process(curve.kind, c, false, curve.reference);
            s.run.clear();
        };
        s.run.clear();
        bool broken = false;  // cut by the near plane or at a vertex: not one closed loop
        for (std::uint32_t i = curve.begin; i + 1 < curve.end; ++i) {
            glm::dvec3 A = curves.point(i), B = curves.point(i + 1);
            const double dA = camera.depth(A) - near, dB = camera.depth(B) - near;
            if (!(dA > 0.0) || !(dB > 0.0)) {
                broken = true;
                if (!(dA > 0.0)) {
                    end_run();  // what came before ends here
                    if (!(dB > 0.0)) continue;
                    A += (B - A) * (dA / (dA - dB));
                } else {
                    B += (A - B) * (dB / (dB - dA));
                }
            }
            const auto [face, face2] = curves.faces(i);
            // A curve that passes through a vertex from one face to another that shares no edge
            // with it can change QI there by what hides the vertex's other faces (local
            // occlusion), and one that passes through a third surface changes QI there: the run
            // ends, and the next starts with a ray test of its own.
            if (!s.run.empty() && (!joined(mesh, s.run.back(), face, face2) || curves.cut(i))) {
                broken = true;
                end_run();
            }
            s.run.push_back({A, B, camera.project(A), camera.project(B), face, face2});
            if (!(dB > 0.0)) end_run();
        }
        const bool loop = curve.closed && !broken && !s.run.empty() &&
                          joined(mesh, s.run.back(), s.run.front().face, s.run.front().face2);
        runs.process(curve.kind, c, loop, curve.reference);
    }
    return st;
}

}  // namespace

SurfaceVisibilityStats surface_visibility(const MeshTopology& mesh, const Features& features, const Camera& camera,
                                          const SurfaceCurves& curves,
                                          const std::function<const RayCaster&()>& rays,
                                          const SurfaceVisibilityOptions& options, SurfaceVisibilityScratch& s,
                                          std::vector<Piece>& out) {
    return visit_curves(mesh, features, camera, SurfaceSource{curves}, rays, options, s, out);
}

SurfaceVisibilityStats intersection_visibility(const MeshTopology& mesh, const Features& features,
                                               const Camera& camera, const IntersectionCurves& curves,
                                               const std::function<const RayCaster&()>& rays,
                                               const SurfaceVisibilityOptions& options,
                                               SurfaceVisibilityScratch& s, std::vector<Piece>& out) {
    SurfaceVisibilityOptions o = options;
    o.pierced_faces = nullptr;  // (every face of theirs is pierced: meets_other says where it matters)
    return visit_curves(mesh, features, camera, IntersectionSource{curves}, rays, o, s, out);
}

}  // namespace inkline
