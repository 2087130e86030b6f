#include "visibility/fast_visibility.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/clock.hpp"

namespace inkline {
namespace {

// Sample states: settled (visible, hidden); ambiguous by the buffer (its centres disagree); near a
// cusp and not clearly hidden; not looked at yet; to be ray-tested (on a pierced face).
constexpr std::uint8_t kVisible = 0, kHidden = 1, kAmbiguous = 2, kNearCusp = 3, kOpen = 4, kExact = 5;

// What the samples of one curve edge share.
struct EdgeView {
    std::uint32_t edge, a, b;  // mesh edge, its vertices in the curve's travel order
    std::uint32_t f0, f1;      // its faces (f1 kNoFace on a border)
    glm::dvec3 A, B;
    glm::dvec2 ia, ib;         // images of A and B
    double zA, zB;
    bool forward;              // edge_vertex[edge][0] == a
    bool silhouette;
    bool back;                 // both faces back-facing (seen only through a hole, if at all)
    glm::dvec2 outward{0.0};   // silhouettes: unit image normal away from their own faces
    // Creases and borders: the planes of their front faces (unit normal, offset); count 0-2.
    glm::dvec3 n[2];
    double d[2];
    int planes = 0;
};

// The settling of samples against the buffer (one view).
class Settler {
public:
    Settler(const MeshTopology& mesh, const Camera& camera, const DepthBuffer& buffer, double margin_px,
            const FaceFacing& face_front, const std::vector<std::uint8_t>* draw)
        : mesh_(mesh), camera_(camera), buffer_(buffer), margin_px_(margin_px), face_front_(face_front), draw_(draw) {
        const glm::dvec2 s = buffer.scale();
        px_world_ = s.x / camera.focal();  // world size of a buffer pixel per unit depth (or absolute, ortho)
    }
    // kVisible, kHidden or kAmbiguous for the point at image q, depth z, on edge `ev`; `share`:
    // the share of the centres looked at that have a face clearly in front.
    std::uint8_t settle(const EdgeView& ev, glm::dvec2 q, double z, float& share) const;

private:
    // -1: no face in front of the sample at centre (i, j); +1: one clearly in front.
    int in_front(const EdgeView& ev, int i, int j, double z, double margin, std::uint32_t& face) const;
    // Whether the surface of face g (a face clearly in front at a centre near q) covers q in
    // front of depth z - eps: 1 yes, -1 no (q lies beyond its outline, or behind it), 0 not found
    // within kWalkSteps faces.
    int walk_to(std::uint32_t g, glm::dvec2 q, double z, double eps) const;
    static constexpr int kWalkSteps = 12;
    // An edge between back faces is near the surface that hides it (the fold): a smaller margin.
    static constexpr double kBackMargin = 0.1;
    double plane_depth(const glm::dvec3& n, double d, glm::dvec2 p) const;
    const MeshTopology& mesh_;
    const Camera& camera_;
    const DepthBuffer& buffer_;
    double margin_px_;
    double px_world_;
    const FaceFacing& face_front_;
    const std::vector<std::uint8_t>* draw_;  // faces in the buffer (null: all)
};

double Settler::plane_depth(const glm::dvec3& n, double d, glm::dvec2 p) const {
    // The line of sight through image point p meets the plane n.x = d at this depth (NaN: no use).
    const double x = (p.x - 0.5 * camera_.width()) / camera_.focal();
    const double y = (0.5 * camera_.height() - p.y) / camera_.focal();
    const glm::dvec3 f = camera_.forward(), r = camera_.right(), u = camera_.upward();
    if (camera_.is_ortho()) {
        const glm::dvec3 o = camera_.eye() + x * r + y * u;
        const double nf = glm::dot(n, f);
        return std::abs(nf) > 1e-12 ? (d - glm::dot(n, o)) / nf : std::nan("");
    }
    const glm::dvec3 dir = f + x * r + y * u;
    const double nd = glm::dot(n, dir);
    const double t = std::abs(nd) > 1e-12 ? (d - glm::dot(n, camera_.eye())) / nd : std::nan("");
    return t > 0.0 ? t : std::nan("");
}

int Settler::in_front(const EdgeView& ev, int i, int j, double z, double margin, std::uint32_t& face) const {
    if (i < 0 || j < 0 || i >= buffer_.width() || j >= buffer_.height()) return -1;
    // The key array first: most centres looked at are empty or behind, and then the face array
    // (another cache line) is not read.
    const double zc = buffer_.depth(i, j);
    if (zc >= z) return -1;  // empty, or behind at the centre
    const std::uint32_t g = buffer_.face(i, j);
    if (g == ev.f0 || g == ev.f1) return -1;
    const auto& t = mesh_.faces[g];
    // The faces around the edge's ends are its own surface (their local occlusion is a cusp's),
    // but for an edge between two back faces: a front face there is the fold that hides it.
    const bool ring = t[0] == ev.a || t[1] == ev.a || t[2] == ev.a || t[0] == ev.b || t[1] == ev.b || t[2] == ev.b;
    if (ring && !(ev.back && face_front_[g])) return -1;
    if (ev.back) {
        face = g;
        return zc < z - kBackMargin * margin ? 1 : -1;
    }
    double own = z;
    if (ev.planes > 0) {
        // A crease's own surface at the centre is near its faces' planes, not at the sample's depth.
        const glm::dvec2 c = buffer_.to_image({i + 0.5, j + 0.5});
        for (int k = 0; k < ev.planes; ++k) {
            const double pz = plane_depth(ev.n[k], ev.d[k], c);
            if (pz == pz) own = std::min(own, std::max(pz, z - 16.0 * margin));
        }
    }
    face = g;
    return zc < own - margin ? 1 : -1;
}

int Settler::walk_to(std::uint32_t g, glm::dvec2 q, double z, double eps) const {
    // Point location by walking the image of the occluder's surface: step across the edge that
    // has q on its far side; leaving the drawn (or same-facing) faces means crossing the
    // occluder's outline.
    const glm::vec2 qb(buffer_.to_buffer(q));
    const std::uint8_t facing = face_front_[g];
    for (int step = 0; step < kWalkSteps; ++step) {
        const auto& t = mesh_.faces[g];
        const glm::vec2 p[3] = {buffer_.vertex(t[0]), buffer_.vertex(t[1]), buffer_.vertex(t[2])};
        const float area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
        int cross = -1;
        for (int k = 0; k < 3 && cross < 0; ++k) {
            const glm::vec2 a = p[k], b = p[(k + 1) % 3];
            const float side = (b.x - a.x) * (qb.y - a.y) - (b.y - a.y) * (qb.x - a.x);
            if (side * area < 0.0f) cross = k;  // q beyond edge k (corners k, k+1)
        }
        if (cross < 0) {  // inside: is this face in front of the sample there?
            const auto& P = mesh_.facing[g];
            const glm::dvec3 n{P.nx, P.ny, P.nz};
            const double zq = plane_depth(n, double(P.d) + glm::dot(n, mesh_.facing_origin), q);
            return zq == zq && zq < z - eps ? 1 : -1;
        }
        const std::uint32_t next = mesh_.face_edges[g].face[cross];
        if (next == kNoFace || (draw_ && !(*draw_)[next]) || face_front_[next] != facing) return -1;
        g = next;
    }
    return 0;
}

std::uint8_t Settler::settle(const EdgeView& ev, glm::dvec2 q, double z, float& share) const {
    const double margin = margin_px_ * px_world_ * (camera_.is_ortho() ? 1.0 : z) + 1e-6 * std::abs(z);
    const glm::dvec2 qb = buffer_.to_buffer(q);
    if (!(qb.x >= 0.0 && qb.y >= 0.0 && qb.x <= buffer_.width() && qb.y <= buffer_.height())) return kExact;
    int front = 0, looked = 0;
    std::uint32_t occluders[9];
    const auto look = [&](int i, int j) {
        ++looked;
        std::uint32_t g = kNoFace;
        if (in_front(ev, i, j, z, margin, g) > 0) occluders[front++] = g;
    };
    if (ev.silhouette) {
        // Centres on the outer side, 0.25-1.8 buffer pixels away: the silhouette's own surface
        // lies on the inner side.
        const int ci = int(std::floor(qb.x)), cj = int(std::floor(qb.y));
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
                const glm::dvec2 off{ci + di + 0.5 - qb.x, cj + dj + 0.5 - qb.y};
                const double out = glm::dot(off, ev.outward);
                if (out < 0.25 || glm::dot(off, off) > 1.8 * 1.8) continue;
                look(ci + di, cj + dj);
            }
    } else {
        // The four centres around the sample.
        const int i0 = int(std::floor(qb.x - 0.5)), j0 = int(std::floor(qb.y - 0.5));
        for (int dj = 0; dj <= 1; ++dj)
            for (int di = 0; di <= 1; ++di) {
                look(i0 + di, j0 + dj);
            }
    }
    share = looked > 0 ? float(front) / float(looked) : 0.5f;
    if (looked == 0) return kAmbiguous;
    if (front == 0) return kVisible;
    if (front == looked) return kHidden;
    // Centres disagree: an occluder's outline passes near. Does the occluder cover the sample?
    bool lost = false;
    for (int k = 0; k < front; ++k) {
        if (std::find(occluders, occluders + k, occluders[k]) != occluders + k) continue;
        const int w = walk_to(occluders[k], q, z, 0.25 * margin);
        if (w > 0) return kHidden;
        lost |= w == 0;
    }
    return lost ? kAmbiguous : kVisible;
}

// Everything about curve edge k of curve c that its samples need.
// `prev`: the curve's previous edge (null for the first), whose end's image and depth are this
// edge's start's.
EdgeView edge_view(const MeshTopology& mesh, const Camera& camera, const Features& features, const FeatureCurve& c,
                   std::size_t k, const EdgeView* prev) {
    EdgeView ev;
    ev.edge = c.edges[k];
    ev.a = c.vertices[k], ev.b = c.vertices[k + 1];
    ev.forward = mesh.edge_vertex[ev.edge][0] == ev.a;
    ev.f0 = mesh.edge_face[ev.edge][0], ev.f1 = mesh.edge_face[ev.edge][1];
    ev.A = mesh.positions[ev.a], ev.B = mesh.positions[ev.b];
    if (prev) ev.ia = prev->ib, ev.zA = prev->zB;
    else ev.ia = camera.project(ev.A), ev.zA = camera.depth(ev.A);
    ev.ib = camera.project(ev.B), ev.zB = camera.depth(ev.B);
    const bool front0 = features.face_front[ev.f0];
    const bool front1 = ev.f1 != kNoFace && features.face_front[ev.f1];
    ev.silhouette = ev.f1 != kNoFace && front0 != front1;
    ev.back = !front0 && !front1;
    if (ev.silhouette && !mesh.is_convex(ev.edge)) {
        // A concave silhouette is hidden where the surface around it is closed (parity), by the
        // fold beside it: looked at as an edge between back faces, all around.
        ev.silhouette = false;
        ev.back = true;
    }
    const auto third = [&](std::uint32_t f) {
        const auto& t = mesh.faces[f];
        for (std::uint32_t v : t)
            if (v != ev.a && v != ev.b) return v;
        return t[0];
    };
    if (ev.silhouette) {
        const glm::dvec2 dir = ev.ib - ev.ia;
        const double len = glm::length(dir);
        const glm::dvec2 nrm = len > 0.0 ? glm::dvec2(-dir.y, dir.x) / len : glm::dvec2(0.0);
        // Both faces lie on the inner side in the image (a fold); the front one's third corner
        // tells which side that is, the back one's if the front one is edge-on.
        for (std::uint32_t f : {front0 ? ev.f0 : ev.f1, front0 ? ev.f1 : ev.f0}) {
            const double side = glm::dot(camera.project(mesh.positions[third(f)]) - ev.ia, nrm);
            if (side != 0.0) {
                ev.outward = side > 0.0 ? -nrm : nrm;
                break;
            }
        }
    } else if (!ev.back) {
        for (std::uint32_t f : {ev.f0, ev.f1})
            if (f != kNoFace && features.face_front[f]) {
                const glm::dvec3 n = mesh.face_normal(f);
                ev.n[ev.planes] = n;
                ev.d[ev.planes] = glm::dot(n, mesh.positions[mesh.faces[f][0]]);
                ++ev.planes;
            }
    }
    return ev;
}

// The 3D parameter along A->B of the point at image parameter t (perspective-correct).
double space_param(const EdgeView& ev, double t, bool ortho) {
    if (ortho) return t;
    const double den = t * ev.zA + (1.0 - t) * ev.zB;
    return den > 0.0 ? t * ev.zA / den : t;
}

}  // namespace

struct FastVisibility::Scratch {
    struct Sample {
        std::uint32_t edge;  // index among the curve's edges
        double t;            // image parameter along it
        double arc;          // image arc length from the curve's start
        std::uint8_t state;
        float share;         // kAmbiguous: share of the centres looked at with a face clearly in front
    };
    std::vector<EdgeView> edges;
    std::vector<Sample> samples;
    std::vector<double> cusps;  // arc lengths of the curve's cusp vertices, increasing
};

namespace {

using Scratch = FastVisibility::Scratch;

// Samples of curve c about `spacing` image pixels apart, each edge at least one; states preset
// where the buffer is not asked (hidden by parity, ray-tested on pierced faces), else kOpen.
// False when the curve reaches the near plane.
bool sample_curve(const MeshTopology& mesh, const Camera& camera, const Features& features, const FeatureCurve& c,
                  double spacing, bool solid, const std::vector<std::uint8_t>* pierced,
                  const std::vector<std::uint8_t>& cusp, Scratch& s) {
    s.edges.clear(), s.samples.clear(), s.cusps.clear();
    double arc = 0.0;
    for (std::size_t k = 0; k < c.edges.size(); ++k) {
        const EdgeView ev = edge_view(mesh, camera, features, c, k, k > 0 ? &s.edges.back() : nullptr);
        if (!(ev.zA > camera.near_distance() && ev.zB > camera.near_distance())) return false;
        std::uint8_t preset = kOpen;
        const bool back0 = !features.face_front[ev.f0];
        const bool back1 = ev.f1 == kNoFace || !features.face_front[ev.f1];
        if (solid && ((back0 && back1) || (ev.silhouette && !mesh.is_convex(ev.edge)))) preset = kHidden;
        else if (pierced && ((*pierced)[ev.f0] || (ev.f1 != kNoFace && (*pierced)[ev.f1]))) preset = kExact;
        if (cusp[ev.a]) s.cusps.push_back(arc);
        const double len = glm::length(ev.ib - ev.ia);
        const int n = std::max(1, int(std::ceil(len / spacing)));
        for (int m = 0; m < n; ++m) {
            const double t = (m + 0.5) / n;
            s.samples.push_back({std::uint32_t(k), t, arc + t * len, preset, 0.0f});
        }
        s.edges.push_back(ev);
        arc += len;
    }
    if (!c.edges.empty() && cusp[c.vertices[c.edges.size()]]) s.cusps.push_back(arc);
    return true;
}

// Settles the open samples by the buffer; near a cusp (where the surface hides itself, at depths
// too close for the buffer) only "hidden" is trusted, anything else is marked kNearCusp.
void settle_samples(const Settler& settler, const Camera& camera, double cusp_px, Scratch& s) {
    std::size_t next_cusp = 0;
    for (Scratch::Sample& x : s.samples) {
        if (x.state != kOpen) continue;
        const EdgeView& ev = s.edges[x.edge];
        while (next_cusp < s.cusps.size() && s.cusps[next_cusp] < x.arc - cusp_px) ++next_cusp;
        const bool near_cusp = next_cusp < s.cusps.size() && std::abs(s.cusps[next_cusp] - x.arc) <= cusp_px;
        const double u = space_param(ev, x.t, camera.is_ortho());
        const double z = ev.zA + u * (ev.zB - ev.zA);
        x.state = settler.settle(ev, ev.ia + x.t * (ev.ib - ev.ia), z, x.share);
        if (near_cusp && x.state != kHidden && x.state != kExact) {
            if (x.state == kVisible) x.share = 0.0f;
            x.state = kNearCusp;
        }
    }
}

// The exact state of sample k (a ray test).
std::uint8_t ray_state(const Camera& camera, const RayCaster& rc, const Scratch& s, std::size_t k) {
    const EdgeView& ev = s.edges[s.samples[k].edge];
    const double u = space_param(ev, s.samples[k].t, camera.is_ortho());
    const glm::dvec3 P = ev.A + u * (ev.B - ev.A);
    return rc.count_layers(camera.ray_origin(P), P, ev.f0, ev.f1) > 0 ? kHidden : kVisible;
}

// Ambiguous samples (an occluder's outline passes among the centres): a run of at most
// `short_run` takes the majority of its centres (the cut then falls where the outline crosses, to
// within a buffer pixel); a longer run, where the buffer cannot tell the layers apart, a ray test
// each. Pierced samples a ray test each. Returns the ray tests made.
std::size_t resolve_ambiguous(const Camera& camera, const std::function<const RayCaster&()>& rays, std::size_t short_run,
                              Scratch& s) {
    std::size_t tests = 0;
    auto& xs = s.samples;
    for (std::size_t r0 = 0; r0 < xs.size();) {
        const std::uint8_t kind = xs[r0].state;
        if (kind != kAmbiguous && kind != kExact) {
            ++r0;
            continue;
        }
        std::size_t r1 = r0;
        while (r1 < xs.size() && xs[r1].state == kind) ++r1;
        for (std::size_t k = r0; k < r1; ++k) {
            if (kind == kAmbiguous && r1 - r0 <= short_run) {
                xs[k].state = xs[k].share >= 0.5f ? kHidden : kVisible;
            } else {
                xs[k].state = ray_state(camera, rays(), s, k);
                ++tests;
            }
        }
        r0 = r1;
    }
    return tests;
}

// Samples near a cusp: the visibility changes at the cusp itself (one branch passes behind the
// fold), so those before the run's first cusp take the state of the sample before the run, those
// after its last cusp the state of the sample after it; where there is none (a curve's end), or
// between two cusps, one ray test decides the stretch. Returns the ray tests made.
std::size_t resolve_near_cusps(const Camera& camera, const std::function<const RayCaster&()>& rays, bool exact_alone,
                               Scratch& s) {
    std::size_t tests = 0;
    auto& xs = s.samples;
    for (std::size_t r0 = 0; r0 < xs.size();) {
        if (xs[r0].state != kNearCusp) {
            ++r0;
            continue;
        }
        std::size_t r1 = r0;
        while (r1 < xs.size() && xs[r1].state == kNearCusp) ++r1;
        const auto first = std::lower_bound(s.cusps.begin(), s.cusps.end(), xs[r0].arc);
        const auto last = std::upper_bound(s.cusps.begin(), s.cusps.end(), xs[r1 - 1].arc);
        const double c0 = first != s.cusps.end() ? *first : xs[r1 - 1].arc + 1.0;
        const double c1 = last != s.cusps.begin() ? *(last - 1) : xs[r0].arc - 1.0;
        // Three stretches: [r0, a) before the first cusp, [a, b) between, [b, r1) after the last.
        std::size_t a = r0, b = r1;
        while (a < r1 && xs[a].arc < c0) ++a;
        while (b > a && xs[b - 1].arc > c1) --b;
        const auto fill = [&](std::size_t lo, std::size_t hi, int neighbour) {
            if (lo >= hi) return;
            std::uint8_t st;
            if (neighbour >= 0 && xs[std::size_t(neighbour)].state <= kHidden) {
                st = xs[std::size_t(neighbour)].state;
            } else if (!exact_alone) {
                for (std::size_t k = lo; k < hi; ++k) xs[k].state = xs[k].share >= 0.5f ? kHidden : kVisible;
                return;
            } else {
                st = ray_state(camera, rays(), s, (lo + hi) / 2);
                ++tests;
            }
            for (std::size_t k = lo; k < hi; ++k) xs[k].state = st;
        };
        fill(r0, a, r0 > 0 ? int(r0 - 1) : -1);
        fill(b, r1, r1 < xs.size() ? int(r1) : -1);
        fill(a, b, -1);
        r0 = r1;
    }
    return tests;
}

// Appends the curve's pieces: runs of equal state, cut halfway between two samples that differ
// (at the vertex between them when they lie on consecutive edges).
void emit_pieces(const MeshTopology& mesh, const Camera& camera, const FeatureCurve& c, std::uint32_t curve,
                 const Scratch& s, std::vector<Piece>& pieces, std::vector<std::vector<EdgeSpan>>& spans,
                 std::size_t& used) {
    if (s.samples.empty()) return;
    const bool ortho = camera.is_ortho();
    const auto edge_param = [&](const EdgeView& ev, double t) {
        const double u = space_param(ev, t, ortho);
        return ev.forward ? u : 1.0 - u;
    };
    // Pieces [0, used) are this view's; those after them are the previous view's, whose storage
    // is taken over (their vectors cleared, capacity kept) instead of allocated anew.
    const auto start = [&](const EdgeView& ev, double t, std::uint8_t state) {
        if (used == pieces.size()) pieces.emplace_back(), spans.emplace_back();
        Piece& p = pieces[used];
        spans[used].clear();
        ++used;
        p.kind = c.kind;
        p.qi = state == kHidden ? 1 : 0;
        p.curve = curve;
        p.object = 0;
        p.opacity.clear(), p.width.clear();
        p.points.clear();
        p.points.push_back(ev.ia + t * (ev.ib - ev.ia));
    };
    const auto extend = [&](const EdgeView& ev, double t0, double t1) {
        pieces[used - 1].points.push_back(ev.ia + t1 * (ev.ib - ev.ia));
        spans[used - 1].push_back({ev.edge, edge_param(ev, t0), edge_param(ev, t1)});
    };
    std::uint8_t state = s.samples[0].state;
    start(s.edges[0], 0.0, state);
    std::size_t k = 0;
    for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
        const EdgeView& ev = s.edges[e];
        double t = 0.0;
        for (; k < s.samples.size() && s.samples[k].edge == e; ++k) {
            if (s.samples[k].state == state) continue;
            state = s.samples[k].state;
            // (the first sample of an edge that differs from the last of the previous one: the
            // cut is at the vertex between them)
            const double cut = (k > 0 && s.samples[k - 1].edge == e) ? 0.5 * (s.samples[k - 1].t + s.samples[k].t) : 0.0;
            if (cut > t) extend(ev, t, cut);
            if (pieces[used - 1].points.size() < 2) --used;  // nothing drawn yet: restart it here
            start(ev, cut, state);
            t = cut;
        }
        extend(ev, t, 1.0);
    }
    (void)mesh;
}

// The image window the buffer covers (`hi` 0: its low corner, 1: its high one): the model's
// projected box, within the image widened by its size on each side (curves beyond that are
// ray-tested; the exact drawing keeps lines outside the image too).
glm::dvec2 buffer_window(const MeshTopology& mesh, const Camera& camera, int hi) {
    const glm::dvec2 size{double(camera.width()), double(camera.height())};
    glm::dvec2 lo = -size, up = 2.0 * size;
    const Bounds3& b = mesh.bounds;
    glm::dvec2 plo{1e300}, phi{-1e300};
    bool all_in_front = true;
    for (int k = 0; k < 8 && all_in_front; ++k) {
        const glm::dvec3 p{k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z};
        all_in_front = camera.depth(p) > camera.near_distance();
        const glm::dvec2 q = camera.project(p);
        plo = glm::min(plo, q), phi = glm::max(phi, q);
    }
    if (all_in_front) lo = glm::max(lo, glm::floor(plo) - 1.0), up = glm::min(up, glm::ceil(phi) + 1.0);
    up = glm::max(up, lo + 1.0);
    return hi ? up : lo;
}

bool eye_outside(const MeshTopology& mesh, const Camera& camera) {
    const Bounds3& b = mesh.bounds;
    if (camera.is_ortho()) {
        // Every corner of the box in front of the eye plane.
        for (int k = 0; k < 8; ++k) {
            const glm::dvec3 p{k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z};
            if (!(camera.depth(p) > camera.near_distance())) return false;
        }
        return true;
    }
    const glm::dvec3 e = camera.eye();
    return e.x < b.lo.x || e.y < b.lo.y || e.z < b.lo.z || e.x > b.hi.x || e.y > b.hi.y || e.z > b.hi.z;
}

}  // namespace

FastVisibilityStats FastVisibility::run(const MeshTopology& mesh, const Features& features, const Camera& camera,
                                        const std::function<const RayCaster&()>& rays, const FeatureOptions& kinds,
                                        const FastVisibilityOptions& options, std::vector<Piece>& pieces,
                                        std::vector<std::vector<EdgeSpan>>& spans) {
    FastVisibilityStats st;
    std::size_t used = 0;  // pieces of this view so far (emit_pieces reuses the storage of those after)
    spans.resize(pieces.size());
    if (!scratch_) scratch_ = std::make_shared<Scratch>();
    const auto t0 = StageClock::now();
    // A closed solid seen from outside: the nearest face anywhere is a front face, and back
    // faces (and concave silhouettes) are hidden.
    const bool solid = mesh.closed && !options.pierced_faces && eye_outside(mesh, camera);
    const std::size_t nf = mesh.face_count();
    if (solid) {
        draw_.resize(nf);
        for (std::size_t f = 0; f < nf; ++f) draw_[f] = features.face_front[std::uint32_t(f)];
    }
    buffer_.reset(camera, options.buffer_px > 0 ? options.buffer_px : std::max(camera.width(), camera.height()),
                  buffer_window(mesh, camera, 0), buffer_window(mesh, camera, 1));
    if (!buffer_.draw(mesh, solid ? &draw_ : nullptr)) {
        st.exact_needed = true;
        pieces.clear(), spans.clear();
        return st;
    }
    st.faces_drawn = buffer_.faces_drawn();
    const auto t1 = StageClock::now();
    st.seconds_buffer = std::chrono::duration<double>(t1 - t0).count();

    cusp_.resize(mesh.vertex_count(), 0);
    for (std::uint32_t v : features.cusp_vertices) cusp_[v] = 1;
    const Settler settler(mesh, camera, buffer_, options.margin_px, features.face_front, solid ? &draw_ : nullptr);
    const double spacing = std::min(buffer_.scale().x, 2.0);  // halfway cuts stay within a pixel
    Scratch& s = *scratch_;
    for (std::size_t c = 0; c < features.curves.size() && !st.exact_needed; ++c) {
        const FeatureCurve& curve = features.curves[c];
        if (!kinds.wants(curve.kind)) continue;
        if (!sample_curve(mesh, camera, features, curve, spacing, solid, options.pierced_faces, cusp_, s)) {
            st.exact_needed = true;
            break;
        }
        settle_samples(settler, camera, options.cusp_px, s);
        st.samples += s.samples.size();
        for (const auto& x : s.samples) st.ambiguous += x.state == kAmbiguous || x.state == kNearCusp;
        const auto tr = StageClock::now();
        const std::size_t tests = st.ray_tests;
        st.ray_tests += resolve_ambiguous(camera, rays, options.short_run, s);
        st.ray_tests += resolve_near_cusps(camera, rays, options.exact_lone_cusps, s);
        if (st.ray_tests > tests) st.seconds_ray_tests += seconds_since(tr);
        emit_pieces(mesh, camera, curve, std::uint32_t(c), s, pieces, spans, used);
    }
    for (std::uint32_t v : features.cusp_vertices) cusp_[v] = 0;
    pieces.resize(used), spans.resize(used);
    if (st.exact_needed) pieces.clear(), spans.clear();
    st.seconds_samples = std::max(0.0, seconds_since(t1) - st.seconds_ray_tests);
    return st;
}

}  // namespace inkline
