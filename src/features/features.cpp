#include "features/features.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cassert>
#include <chrono>
#include <cmath>
#include <functional>

#include "core/predicates.hpp"
#include "features/facing_kernels.hpp"
#include "model/orientation.hpp"

namespace inkline {

const char* finder_name(FinderKind k) { return k == FinderKind::Randomized ? "randomized" : "exhaustive"; }

bool face_is_front(const MeshTopology& mesh, std::uint32_t face, const Camera& camera) {
    const auto& v = mesh.faces[face];
    const glm::dvec3 &a = mesh.positions[v[0]], &b = mesh.positions[v[1]], &c = mesh.positions[v[2]];
    return orient_eye(camera, a, b, c) > 0;
}

namespace {

constexpr std::uint8_t kSil = std::uint8_t(LineKind::Silhouette);
constexpr std::uint8_t kBorder = std::uint8_t(LineKind::Border);
constexpr std::uint8_t kCrease = std::uint8_t(LineKind::Crease);
using VertexScratch = Features::VertexScratch;

bool is_silhouette(const MeshTopology& mesh, const Features& f, std::uint32_t e) {
    const auto [f0, f1] = mesh.edge_face[e];
    return f1 != kNoFace && silhouette_from_facing(mesh, e, f.face_front[f0], f.face_front[f1]);
}

// The exhaustive scan's kernels compare the two faces' facing bits only: on a non-orientable
// mesh its silhouette list is corrected on the seam edges (their own sorted list), keeping the
// list in edge order.
void correct_seam_silhouettes(const MeshTopology& mesh, Features& out) {
    auto& sil = out.silhouette_edges;
    std::erase_if(sil, [&](std::uint32_t e) {
        if (!mesh.is_seam(e)) return false;
        out.edge_kind[e] = kNoKind;
        return true;
    });
    const std::size_t kept = sil.size();
    for (std::uint32_t e : mesh.seam_list)
        if (is_silhouette(mesh, out, e)) {
            out.edge_kind[e] = kSil;
            sil.push_back(e);
        }
    std::inplace_merge(sil.begin(), sil.begin() + std::ptrdiff_t(kept), sil.end());
}

// Static kinds: borders always, creases unless they are silhouettes. Returns crease edges that are
// silhouettes through `on_silhouette` (the exhaustive scan has them already).
template <class OnSilhouette>
void classify_static(const MeshTopology& mesh, Features& out, OnSilhouette on_silhouette) {
    for (std::uint32_t e : mesh.border_list) {
        out.edge_kind[e] = kBorder;
        out.border_edges.push_back(e);
    }
    for (std::uint32_t e : mesh.crease_list) {
        if (out.edge_kind[e] == kSil) continue;
        if (is_silhouette(mesh, out, e)) {
            on_silhouette(e);
        } else {
            out.edge_kind[e] = kCrease;
            out.crease_edges.push_back(e);
        }
    }
}

// Whether a face around border vertex v may hide one of v's border edges near v in the image: the
// far end of the edge seen from v inside (or on the boundary of) the image of another face's
// corner at v, decided by exact image orientations. The faces around v are all of one facing (a
// change of facing would put a silhouette edge at v), so this happens exactly where their images
// wind a full turn or more about v. A face seen edge-on covers nothing; the edge's image on the
// boundary of a corner's, and vertices not in front of the near plane (no image), count as folded.
bool border_fan_folds(const MeshTopology& mesh, const Camera& camera, std::uint32_t v) {
    const double near = camera.near_distance();
    const glm::dvec3& V = mesh.positions[v];
    if (!(camera.depth(V) > near)) return true;
    const std::uint32_t k0 = mesh.vertex_edge_begin[v], k1 = mesh.vertex_edge_begin[v + 1];
    for (std::uint32_t kb = k0; kb < k1; ++kb) {
        const std::uint32_t b = mesh.vertex_edges[kb];
        if (mesh.edge_face[b][1] != kNoFace) continue;  // a border edge of v, its one face
        const glm::dvec3& W = mesh.positions[mesh.edge_vertex[b][0] == v ? mesh.edge_vertex[b][1] : mesh.edge_vertex[b][0]];
        if (!(camera.depth(W) > near)) return true;
        bool folds = false;
        for_each_face_around(mesh, v, [&](std::uint32_t f) {  // (the test is the same for either winding)
            if (folds || f == mesh.edge_face[b][0]) return;
            const auto& c = mesh.faces[f];
            const int i = c[0] == v ? 0 : c[1] == v ? 1 : 2;
            const glm::dvec3 &A = mesh.positions[c[(i + 1) % 3]], &B = mesh.positions[c[(i + 2) % 3]];
            if (!(camera.depth(A) > near) || !(camera.depth(B) > near)) {
                folds = true;
                return;
            }
            const int o = image_orientation(camera, V, A, B);
            if (o == 0) return;  // seen edge-on: its image covers no direction from v
            folds = image_orientation(camera, V, A, W) != -o && image_orientation(camera, V, W, B) != -o;
        });
        if (folds) return true;
    }
    return false;
}

// The view's feature edges numbered locally, as the three lists in a row (silhouettes, borders,
// creases), and their vertices in order of first use (Features::chain_vertices, chain_links).
struct FeatureNumbering {
    std::uint32_t edges = 0;                // feature edges: [0, list_end[0]) silhouettes, then borders, creases
    std::uint32_t vertices = 0;             // vertices numbered
    std::uint32_t silhouette_vertices = 0;  // the first ones: the vertices of silhouette edges
    std::size_t list_end[3] = {0, 0, 0};
    std::uint8_t kind_of(std::uint32_t i) const { return i < list_end[0] ? kSil : i < list_end[1] ? kBorder : kCrease; }
};

constexpr std::uint32_t kBreak = UINT32_MAX;  // ChainLink::next where the vertex breaks chains

// The one pass over the feature edges that gathers what each vertex needs: counts, kinds, and
// the xor of its feature edges (at a vertex of degree two: the other edge). The mesh's per-vertex
// and per-edge arrays are read once per edge here; everything after reads the compact arrays.
FeatureNumbering number_feature_edges(const MeshTopology& mesh, Features& out) {
    const std::vector<std::uint32_t>* lists[3] = {&out.silhouette_edges, &out.border_edges, &out.crease_edges};
    const std::uint8_t list_kind[3] = {kSil, kBorder, kCrease};
    const std::size_t n = out.silhouette_edges.size() + out.border_edges.size() + out.crease_edges.size();
    auto& local = out.vertex_local;
    if (local.size() != mesh.vertex_count()) local.assign(mesh.vertex_count(), UINT32_MAX);
    auto& verts = out.chain_vertices;
    auto& links = out.chain_links;
    // (at most two vertices per edge; slot nv is written on every first-use test, so it must exist)
    if (verts.size() < 2 * n + 1) verts.resize(2 * n + 1);
    std::uint32_t nv = 0;  // vertices numbered so far
    links.resize(n);
    FeatureNumbering num;
    std::uint32_t i = 0;
    for (int l = 0; l < 3; ++l) {
        const std::uint8_t kind = list_kind[l];
        const std::uint32_t* list = lists[l]->data();
        const std::size_t m = lists[l]->size();
        for (std::size_t j = 0; j < m; ++j) {
            // The edges are scattered over the mesh: their vertices and flags are fetched 32
            // edges ahead and those vertices' local numbers 16 ahead, so that the misses overlap.
            if (j + 32 < m) {
                __builtin_prefetch(&mesh.edge_vertex[list[j + 32]]);
                __builtin_prefetch(&mesh.edge_flags[list[j + 32]]);
            }
            if (j + 16 < m) {
                const auto& ahead = mesh.edge_vertex[list[j + 16]];
                __builtin_prefetch(&local[ahead[0]], 1);
                __builtin_prefetch(&local[ahead[1]], 1);
            }
            const std::uint32_t e = list[j];
            const bool front = kind == kSil && mesh.is_convex(e);
            Features::ChainLink& link = links[i];
            link.edge = e;
            link.used = 0;
            for (int k = 0; k < 2; ++k) {
                const std::uint32_t v = mesh.edge_vertex[e][k];
                // First use without a branch (it would be mispredicted about half the
                // time): the next slot is always written, and kept only for a new vertex.
                const std::uint32_t old = local[v];
                const bool fresh = old == UINT32_MAX;
                const std::uint32_t lv = fresh ? nv : old;
                local[v] = lv;
                verts[nv] = {v, 0, 0, 0, 0, 0, 0};
                nv += fresh;
                Features::ChainVertex& s = verts[lv];
                link.end[k] = lv;
                s.edge_xor ^= i;
                if (s.degree < 255) ++s.degree;
                if (kind == kSil && s.silhouettes < 255) ++s.silhouettes;
                if (front && s.front < 255) ++s.front;
                s.kinds |= std::uint8_t(1u << kind);
            }
            ++i;
        }
        num.list_end[l] = i;
        if (l == 0) num.silhouette_vertices = nv;
    }
    num.edges = i;
    num.vertices = nv;
    return num;
}

// Cusps (Definition 3) at the vertices of silhouette edges, listed in the order the edges first
// use them. A border that turns on at a vertex (its only feature edges two borders) may change
// QI there too, where the faces around the vertex fold over in the image (a ruffled or folded
// border; Definition 3's cusps are silhouette vertices only): such a vertex breaks the chain
// (marked as a cusp is, not listed), so that the visibility stage measures the local occlusion
// of each side there. (A break where none is needed only adds a curve end.)
void mark_cusps(const MeshTopology& mesh, const Camera& camera, const FeatureNumbering& num, Features& out) {
    auto& verts = out.chain_vertices;
    const bool seams = !mesh.seam_list.empty();
    for (std::uint32_t lv = 0; lv < num.silhouette_vertices; ++lv) {
        Features::ChainVertex& s = verts[lv];
        CuspCase c = CuspCase::None;
        if (s.silhouettes > 2) c = CuspCase::ManySilhouettes;
        else if (s.kinds & (1u << kBorder)) c = CuspCase::BorderEdge;
        else if (s.silhouettes == 2 && s.front == 1) c = CuspCase::FrontBackMeet;
        // On an orientation seam the two edges' convexity is relative to opposite windings, so
        // front and back cannot be told apart there: the vertex breaks the chain, and the
        // visibility stage measures each side's occlusion (a break where none is needed only adds
        // a curve end).
        else if (seams && on_orientation_seam(mesh, s.id)) c = CuspCase::FrontBackMeet;
        if (c != CuspCase::None) {
            s.cusp = 1;
            out.cusp_vertices.push_back(s.id);
            out.cusp_cases.push_back(c);
        }
    }
    for (std::uint32_t lv = num.silhouette_vertices; lv < num.vertices; ++lv) {
        Features::ChainVertex& s = verts[lv];
        if (s.degree == 2 && s.kinds == (1u << kBorder) && border_fan_folds(mesh, camera, s.id)) s.cusp = 1;
    }
}

// Each feature edge gets, in one pass whose reads are independent of each other, the edge that
// follows it through each of its vertices (kBreak where the vertex breaks chains: not two
// feature edges, two of different kinds, or a cusp): a step of a chain (a chain of dependent
// reads) then reads one record instead of an edge and then its vertex.
void link_chains(const FeatureNumbering& num, Features& out) {
    const auto& verts = out.chain_vertices;
    auto is_break = [&](const Features::ChainVertex& s) {
        return s.cusp || s.degree != 2 || (s.kinds & (s.kinds - 1)) != 0;
    };
    for (std::uint32_t i = 0; i < num.edges; ++i) {
        Features::ChainLink& link = out.chain_links[i];
        for (int k = 0; k < 2; ++k) {
            const Features::ChainVertex& s = verts[link.end[k]];
            link.next[k] = is_break(s) ? kBreak : s.edge_xor ^ i;  // the other of its two feature edges
            link.id[k] = s.id;
        }
    }
}

// The curves of the requested kinds: chains from every break, then the closed loops left.
void walk_chains(const FeatureNumbering& num, const FeatureOptions& options, Features& out) {
    const auto& verts = out.chain_vertices;
    auto& links = out.chain_links;
    auto& curves = out.curves;  // (its arrays keep their storage from view to view)
    curves.clear();
    // A chain from the local vertex start_v along feature edge start_i.
    auto walk = [&](std::uint32_t start_v, std::uint32_t start_i) {
        curves.start(LineKind(num.kind_of(start_i)), verts[start_v].id);
        std::uint32_t i = start_i;
        int out_end = links[i].end[0] == start_v ? 1 : 0;  // the end of edge i the chain leaves by
        while (true) {
            Features::ChainLink& link = links[i];
            link.used = 1;
            const std::uint32_t v = link.end[out_end];
            curves.add(link.edge, link.id[out_end]);
            const std::uint32_t next = link.next[out_end];
            if (v == start_v) {  // a loop; closed only if it may continue through its start
                curves.set_closed(next != kBreak);
                break;
            }
            if (next == kBreak || links[next].used) break;
            i = next;
            out_end = links[i].end[0] == v ? 1 : 0;
        }
    };
    const std::uint32_t n = num.edges;
    for (std::uint32_t i = 0; i < n; ++i) {
        if (links[i].used || !options.wants(LineKind(num.kind_of(i)))) continue;
        for (int k = 0; k < 2; ++k)
            if (!links[i].used && links[i].next[k] == kBreak) walk(links[i].end[k], i);
    }
    for (std::uint32_t i = 0; i < n; ++i)  // what is left are closed loops without a break
        if (!links[i].used && options.wants(LineKind(num.kind_of(i)))) walk(links[i].end[0], i);
    curves.finish();
}

// Leaves the per-vertex arrays as they were before the view (the finder's marks cleared).
void clear_vertex_marks(const FeatureNumbering& num, Features& out) {
    auto& local = out.vertex_local;
    const auto& verts = out.chain_vertices;
    const std::uint32_t nv = num.vertices;
    for (std::uint32_t k = 0; k < nv; ++k) {
        if (k + 16 < nv) {
            __builtin_prefetch(&local[verts[k + 16].id], 1);
            __builtin_prefetch(&out.vertex_scratch[verts[k + 16].id], 1);
        }
        const Features::ChainVertex& s = verts[k];
        local[s.id] = UINT32_MAX;
        out.vertex_scratch[s.id] = {};
    }
}

// Cusps (Definition 3) over the vertices of silhouette edges, then the chaining into curves.
// A vertex breaks chains where the number of feature edges (of every kind, drawn or not) is not
// two, where the two differ in kind, or at a cusp. Everything a vertex needs is gathered in one
// pass over the feature edges, so no vertex ring is scanned; the cusps and the chaining then read
// only compact local arrays (this stage is bound by the latency of scattered reads).
void cusps_and_curves(const MeshTopology& mesh, const Camera& camera, const FeatureOptions& options, Features& out) {
    const FeatureNumbering num = number_feature_edges(mesh, out);
    mark_cusps(mesh, camera, num, out);
    link_chains(num, out);
    walk_chains(num, options, out);
    clear_vertex_marks(num, out);
}

}  // namespace

Features extract_features(const MeshTopology& mesh, const Camera& camera, const FeatureOptions& options) {
    Features out;
    SilhouetteFinder(mesh).find(camera, options, out);
    return out;
}

SilhouetteFinder::SilhouetteFinder(const MeshTopology& mesh, const FinderOptions& options)
    : mesh_(&mesh), opt_(options), rng_(options.seed) {}

void SilhouetteFinder::reset() {
    previous_.clear();
    complete_ = false;
    stamp_ = 0;
    carried_ = {};
    rng_.seed(opt_.seed);
}

void SilhouetteFinder::stamp(Features& out) {
    static std::atomic<std::uint64_t> next{1};  // unique over all finders of the process
    stamp_ = next.fetch_add(1, std::memory_order_relaxed);
    out.silhouette_marks = stamp_;
}

void SilhouetteFinder::find(const Camera& camera, const FeatureOptions& options, Features& out,
                            const std::function<void()>& searched) {
    const MeshTopology& mesh = *mesh_;
    const std::size_t ne = mesh.edge_count(), nv = mesh.vertex_count();
    // Recycle: reset what the previous view of `out` marked. A view that follows a complete
    // silhouette whose marks `out` holds (left by this finder's last view: its silhouette list
    // is previous_) keeps them: follow() rewrites only the edges of faces that turned.
    marks_kept_ = opt_.kind == FinderKind::Randomized && opt_.coherence && complete_ && !previous_.empty() &&
                  stamp_ != 0 && out.silhouette_marks == stamp_ && out.edge_kind.size() == ne &&
                  out.silhouette_edges.size() == previous_.size();
    stamp_ = 0;
    out.silhouette_marks = 0;
    if (out.edge_kind.size() != ne) {
        out.edge_kind.assign(ne, kNoKind);
    } else {
        for (const auto* list : {&out.silhouette_edges, &out.border_edges, &out.crease_edges}) {
            if (marks_kept_ && list == &out.silhouette_edges) continue;
            for (std::uint32_t e : *list) out.edge_kind[e] = kNoKind;
        }
    }
    if (out.vertex_scratch.size() != nv) out.vertex_scratch.assign(nv, VertexScratch{});
    out.silhouette_edges.clear();
    out.border_edges.clear();
    out.crease_edges.clear();
    out.cusp_vertices.clear();
    out.cusp_cases.clear();
    out.stats = {};
    out.stats.finder = opt_.kind;

    planes_read_ = 0;
    ++views_;
    const auto t0 = std::chrono::steady_clock::now();
    if (opt_.kind == FinderKind::Exhaustive) {
        // One view alone (extract_features) does not build the blocks; a finder that lives
        // across views does, on its second.
        out.face_front.begin_full(mesh, camera, opt_.threads, ++full_views_ > 1 ? blocks() : nullptr, &team_);
        planes_read_ += out.face_front.planes_read();
        scan_exhaustive(out);
    } else if (opt_.coherence && opt_.first_full && previous_.empty()) {
        // The band's rebuilds need the face blocks: built here, in the facing pass (the planes
        // read once); the edge scan reads every edge (ranges of edges by block would cost a pass
        // over the edges to build, for this one view).
        if (opt_.blocks && opt_.threads <= 1 && !blocks_.built_for(mesh))
            out.face_front.begin_full_building(mesh, camera, blocks_);
        else
            out.face_front.begin_full(mesh, camera, opt_.threads, blocks(), &team_);
        planes_read_ += out.face_front.planes_read();
        scan_exhaustive(out, false);
        out.stats.finder = FinderKind::Randomized;
        out.stats.fraction = opt_.fraction;
        previous_.assign(out.silhouette_edges.begin(), out.silhouette_edges.end());
        previous_sorted_ = std::is_sorted(previous_.begin(), previous_.end());
        previous_camera_ = camera;
        previous_filter_.bind(mesh, camera);
        complete_ = true;
        carried_ = {&out.face_front, out.face_front.generation()};
        stamp(out);
    } else {
        // Following a complete silhouette, the previous view's full facing (still in `out`, as
        // left there) is carried on by flipping the faces that turned: the visibility stage then
        // reads a full view instead of deciding faces on first use.
        const bool carry = complete_ && opt_.coherence && !previous_.empty() && carried_.facing == &out.face_front &&
                           carried_.generation == out.face_front.generation() && out.face_front.full();
        carried_ = {};
        if (!carry) out.face_front.begin_lazy(mesh, camera);
        search_randomized(camera, out, carry);
    }
    const auto t1 = std::chrono::steady_clock::now();
    out.stats.planes_read = planes_read_;
    if (searched) searched();
    cusps_and_curves(mesh, camera, options, out);
    out.stats.seconds_search = std::chrono::duration<double>(t1 - t0).count();
    out.stats.seconds_chain = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    for (std::uint32_t v : sought_) out.vertex_scratch[v].sought = 0;
    sought_.clear();
    out.stats.faces_decided = out.face_front.faces_decided();
    out.stats.exact_facing_tests = out.face_front.exact_tests();
}

const FaceBlocks* SilhouetteFinder::blocks() {
    if (!opt_.blocks) return nullptr;
    if (!blocks_.built_for(*mesh_)) blocks_.build(*mesh_);
    return &blocks_;
}

void SilhouetteFinder::scan_exhaustive(Features& out, bool block_edges) {
    const MeshTopology& mesh = *mesh_;
    const std::uint32_t ne = std::uint32_t(mesh.edge_count()), nf = std::uint32_t(mesh.face_count());
    // Branchless pass over blocks of edges: every edge whose two face states differ (or are both
    // undecided; borders meet the sentinel) is a candidate; candidates are then decided exactly,
    // in edge order, on this thread (the exact facing caches what it computes).
    constexpr std::uint32_t kBlock = 4096;
    const auto* ef = mesh.edge_face.data();
    const std::uint8_t* st = out.face_front.states();
    const FacingKernels& kernels = facing_kernels();
    auto collect_range = [&](std::uint32_t lo, std::uint32_t hi, std::vector<std::uint32_t>& cand) {
        for (std::uint32_t e0 = lo; e0 < hi; e0 += kBlock) {
            const std::uint32_t e1 = std::min(hi, e0 + kBlock), n0 = std::uint32_t(cand.size());
            cand.resize(n0 + (e1 - e0));
            const std::uint32_t n = kernels.edge_candidates(ef, st, nf, e0, e1, cand.data() + n0);
            cand.resize(n0 + n);
        }
    };
    // With the facing decided by blocks, the edges of a block whose faces and neighbour blocks
    // all have one state (FaceBlocks::edges_uniform) are not read: none is a candidate. The
    // other edges are scanned in runs, in edge order (the same candidates).
    // From the second view, where the CPU has the kernel: the gather-free layout (BlockEdges),
    // block by block (it skips the blocks whose windows hold one state itself, as fast as
    // skipping by the block states: bench/results/finder.md); its candidates of decided faces
    // are silhouettes.
    if (block_edges && opt_.edge_windows && full_views_ > 1 && BlockEdges::has_simd() && !block_edges_tried_) {
        block_edges_tried_ = true;
        block_edges_.build(mesh);
    }
    const BlockEdges* be = block_edges && opt_.edge_windows && full_views_ > 1 && block_edges_.built_for(mesh) ? &block_edges_ : nullptr;
    static const std::vector<std::uint8_t> no_states;
    const std::vector<std::uint8_t>& cls = block_edges ? out.face_front.block_states() : no_states;
    if (!be && !cls.empty() && blocks_.built_for(mesh) && !blocks_.edges_tried()) blocks_.build_edges();
    const FaceBlocks* fb = !be && !cls.empty() && blocks_.built_for(mesh) && blocks_.has_edges() ? &blocks_ : nullptr;
    const std::uint32_t units = be ? std::uint32_t(be->size()) : fb ? std::uint32_t(fb->size()) : ne;  // edges, or blocks of faces
    const std::uint32_t parts = ne < 65536 ? 1u : std::uint32_t(std::clamp(opt_.threads, 1, 64));
    auto& lists = out.thread_candidates;
    if (lists.size() < parts) lists.resize(parts);
    std::vector<std::size_t> read(parts, 0);  // edges read, per part
    auto collect = [&](std::uint32_t lo, std::uint32_t hi, std::uint32_t part) {
        std::vector<std::uint32_t>& cand = lists[part];
        cand.clear();
        if (be) {
            read[part] = be->scan(st, lo, hi, [](std::uint32_t) { return false; }, cand);
            return;
        }
        if (!fb) return collect_range(lo, hi, cand);
        // lo, hi are block numbers here
        std::uint32_t open = UINT32_MAX;
        for (std::uint32_t b = lo; b <= hi; ++b) {
            const bool skip = b == hi || fb->edges_uniform(b, cls.data());
            const std::uint32_t e = fb->edge_begin(b);
            if (!skip && open == UINT32_MAX) open = e;
            if (skip && open != UINT32_MAX) {
                read[part] += e - open;
                collect_range(open, e, cand);
                open = UINT32_MAX;
            }
        }
    };
    const std::uint32_t step = (units + parts - 1) / parts;
    team_.run(int(parts), [&](int i) {
        const std::uint32_t k = std::uint32_t(i);
        collect(std::min(units, k * step), std::min(units, (k + 1) * step), k);
    });
    for (std::uint32_t i = 0; i < parts; ++i)
        for (std::uint32_t e : lists[i]) {
            if (be) {  // unflagged: decided faces that differ
                const bool check = e & BlockEdges::kCheck;
                e &= ~BlockEdges::kCheck;
                if (check && !is_silhouette(mesh, out, e)) continue;
            } else if (!is_silhouette(mesh, out, e)) {
                continue;
            }
            out.edge_kind[e] = kSil;
            out.silhouette_edges.push_back(e);
        }
    if (!mesh.seam_list.empty()) correct_seam_silhouettes(mesh, out);
    classify_static(mesh, out, [](std::uint32_t) {});  // crease silhouettes were scanned already
    out.stats.fraction = 1.0;
    out.stats.edges_examined = ne;
    out.stats.edges_read = ne;
    if (fb || be) {
        out.stats.edges_read = 0;
        for (std::size_t r : read) out.stats.edges_read += r;
    }
}

// Vose's alias method: O(edges) once, O(1) per draw.
void SilhouetteFinder::build_table() {
    const MeshTopology& mesh = *mesh_;
    const std::size_t ne = mesh.edge_count();
    alias_prob_.assign(ne, 0.0f);
    alias_.assign(ne, 0);
    double total = 0.0;
    for (std::size_t e = 0; e < ne; ++e) total += mesh.edge_normal_angle[e];
    if (!(total > 0.0)) {  // all flat: uniform
        std::fill(alias_prob_.begin(), alias_prob_.end(), 1.0f);
        return;
    }
    std::vector<double> scaled(ne);
    std::vector<std::uint32_t> small, large;
    for (std::uint32_t e = 0; e < ne; ++e) {
        scaled[e] = mesh.edge_normal_angle[e] * double(ne) / total;
        (scaled[e] < 1.0 ? small : large).push_back(e);
    }
    while (!small.empty() && !large.empty()) {
        const std::uint32_t s = small.back(), l = large.back();
        small.pop_back();
        alias_prob_[s] = float(scaled[s]);
        alias_[s] = l;
        scaled[l] -= 1.0 - scaled[s];
        if (scaled[l] < 1.0) {
            large.pop_back();
            small.push_back(l);
        }
    }
    for (std::uint32_t e : large) alias_prob_[e] = 1.0f, alias_[e] = e;
    for (std::uint32_t e : small) alias_prob_[e] = 1.0f, alias_[e] = e;  // rounding leftovers
}

// Marks e and every silhouette edge connected to it through vertices (the whole curve, and the
// curves it meets at junctions).
void SilhouetteFinder::trace(std::uint32_t e, Features& out) {
    const MeshTopology& mesh = *mesh_;
    add_silhouette(e, out);
    stack_.clear();
    stack_.push_back(e);
    while (!stack_.empty()) {
        const std::uint32_t g = stack_.back();
        stack_.pop_back();
        for (std::uint32_t v : mesh.edge_vertex[g]) {
            if (out.vertex_scratch[v].traced) continue;
            out.vertex_scratch[v].traced = 1;
            for (std::uint32_t k = mesh.vertex_edge_begin[v]; k < mesh.vertex_edge_begin[v + 1]; ++k) {
                const std::uint32_t h = mesh.vertex_edges[k];
                if (out.edge_kind[h] != kNoKind) continue;  // found, or a border or (non-silhouette) crease
                ++out.stats.edges_examined;
                if (is_silhouette(mesh, out, h)) {
                    add_silhouette(h, out);
                    stack_.push_back(h);
                }
            }
        }
    }
}

// Bounded seek (section 4.1) from vertex v on a region of one facing (`front`): from a
// back-facing region toward the camera (to the neighbour of least depth), from a front-facing one
// away from it (greatest depth), until a vertex with a silhouette edge is reached (traced), or
// the step bound, or a vertex with no neighbour further along. Depth only steers the walk;
// silhouettes are decided by the exact facing.
void SilhouetteFinder::seek(std::uint32_t v, bool front, const Camera& camera, Features& out) {
    const MeshTopology& mesh = *mesh_;
    ++out.stats.seeks;
    const double sign = front ? 1.0 : -1.0;  // maximise sign * depth
    double here = sign * camera.depth(mesh.positions[v]);
    for (int step = 0; step < opt_.step_bound; ++step) {
        // A vertex another seek has passed this view leads where that seek went: stop.
        auto& mark = out.vertex_scratch[v];
        if (mark.sought) return;
        mark.sought = 1;
        sought_.push_back(v);
        ++out.stats.seek_steps;
        std::uint32_t next = UINT32_MAX;
        double best = here;
        for (std::uint32_t k = mesh.vertex_edge_begin[v]; k < mesh.vertex_edge_begin[v + 1]; ++k) {
            const std::uint32_t h = mesh.vertex_edges[k];
            if (out.edge_kind[h] == kSil) return;  // reached a silhouette found already
            ++out.stats.edges_examined;
            if (out.edge_kind[h] != kBorder && is_silhouette(mesh, out, h)) {
                ++out.stats.seek_hits;
                trace(h, out);
                return;
            }
            const std::uint32_t u = mesh.edge_vertex[h][0] == v ? mesh.edge_vertex[h][1] : mesh.edge_vertex[h][0];
            const double d = sign * camera.depth(mesh.positions[u]);
            if (d > best) best = d, next = u;
        }
        if (next == UINT32_MAX) return;
        v = next;
        here = best;
    }
}

void SilhouetteFinder::add_silhouette(std::uint32_t e, Features& out) {
    out.edge_kind[e] = kSil;
    out.silhouette_edges.push_back(e);
}

namespace {
// The vector the facing filter dots the planes with (eye - facing_origin, or -forward for an
// orthographic camera) in double, and w (1 perspective, 0 orthographic).
void eye_vector(const MeshTopology& mesh, const Camera& camera, double e[3], double& w) {
    const bool ortho = camera.is_ortho();
    const glm::dvec3 v = ortho ? -camera.forward() : camera.eye() - mesh.facing_origin;
    e[0] = v.x, e[1] = v.y, e[2] = v.z;
    w = ortho ? 0.0 : 1.0;
}

double distance3(const double a[3], const double b[3]) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// Per 64 faces (and one past the last), the first edge whose first face is one of them, where the
// mesh numbers its edges in the order of their first face (topology.cpp); else {0}. (The same
// ranges as FaceBlocks::build_edges, built alone because that also lists each block's
// neighbours, several times the cost: bench/results/finder.md.)
std::vector<std::uint32_t> first_edges_by_64_faces(const MeshTopology& mesh) {
    const std::size_t ne = mesh.edge_count();
    for (std::size_t e = 1; e < ne; ++e)
        if (mesh.edge_face[e][0] < mesh.edge_face[e - 1][0]) return {0};
    std::vector<std::uint32_t> first(mesh.face_count() / 64 + 2, std::uint32_t(ne));
    for (std::size_t e = ne; e-- > 0;) first[mesh.edge_face[e][0] >> 6] = std::uint32_t(e);
    for (std::size_t b = first.size() - 1; b-- > 0;) first[b] = std::min(first[b], first[b + 1]);
    return first;
}
}  // namespace

// The band: every face whose float distance to the eye e is within margin + bound. With the
// float distance within bound/2 of the exact one (facing.cpp) and a unit normal, the exact
// distance moves by at most |e' - e| when the eye moves to e', so a face outside the band keeps
// its facing for every eye within `margin` of e. Untrusted (NaN) planes are always in the band.
// The face blocks skip the blocks whose planes are all beyond the margin. The faces outside the
// band get their front bit here, from the sign of their float distance (beyond the filter's
// bound, so exact), which they keep for every such eye; the band's bits are set by follow().
// The pass writes the band's rows as it reads the planes (FacingBand::select), so that a rebuild
// reads each plane once; outer bands and band-local face records cost more than they saved
// (bench/results/finder_targets.md, bench/results/finder.md).
void SilhouetteFinder::build_band(const double eye[3], double w, double margin) {
    const MeshTopology& mesh = *mesh_;
    FacingFilter at;  // the filter of the band's eye (not the view's, when the band is built ahead of it)
    at.bind(mesh, eye, w);
    const float limit = float((margin + double(at.bound)) * (1.0 + 0x1p-20));
    planes_read_ += band_.select(mesh, at, limit, blocks(), front_bits_.data());
    for (int i = 0; i < 3; ++i) band_eye_[i] = eye[i];
    band_w_ = w;
    band_margin_ = margin;
}

// Frame coherence (exact). Every face that changed facing since the previous view lies in the band
// (streamed: plane copies, no mesh access); an edge whose two faces kept their facing is a
// silhouette now exactly when it was one in the previous view, so the silhouette is the previous
// edges none of whose faces turned, plus the edges of the faces that turned whose two faces differ
// now. Given the previous view's silhouette complete, so is this one; silhouette curves the
// previous view missed are found here only where their faces turn (or by the draws).
void SilhouetteFinder::follow(const Camera& camera, Features& out) {
    start_following(camera);
    const bool rebuilt = update_band(camera);
    out.stats.band_rebuilt = rebuilt;
    out.stats.band_faces = band_.size();
    find_turned_faces(out, rebuilt);
    out.stats.faces_turned = turned_.size();
    const std::size_t rechecked = reclassify_turned_edges(out);
    merge_silhouette(out, rechecked);
    std::uint64_t* turned = turned_bits_.data();
    for (std::uint32_t f : turned_) turned[f >> 6] = 0;
}

// Sizes the per-face bits for the mesh and binds this view's filter. The band's faces keep their
// bits from the previous view: if that view did not run follow() (a first view, a view after
// reset(), or one after a view with no silhouette), the bits are older, and the band is rebuilt.
void SilhouetteFinder::start_following(const Camera& camera) {
    const MeshTopology& mesh = *mesh_;
    const std::size_t nf = mesh.face_count();
    if (front_bits_.size() != nf / 64 + 1) {
        band_margin_ = -1.0;
        for (auto* bits : {&front_bits_, &turned_bits_}) bits->assign(nf / 64 + 1, 0);
    }
    if (bits_view_ + 1 != views_) band_margin_ = -1.0;
    bits_view_ = views_;
    camera_ = camera;
    filter_.bind(mesh, camera);
}

// Keeps the band while both eyes lie within its margin of where it was built, else rebuilds it
// (and retunes its size). Returns whether it was rebuilt.
bool SilhouetteFinder::update_band(const Camera& camera) {
    const MeshTopology& mesh = *mesh_;
    double e[3], w, p[3], pw;
    eye_vector(mesh, camera, e, w);
    eye_vector(mesh, previous_camera_, p, pw);
    const double step = distance3(e, p);
    if (w != pw) {
        // Between a perspective and an orthographic view (an eye point and a view direction) no
        // distance bounds the change of the faces' signed distances: every face is in the band,
        // for this view only (the next view builds a band about its eye).
        build_band(e, w, INFINITY);
        band_margin_ = -1.0;
        return true;
    }
    if (band_margin_ >= 0.0 && w == band_w_ && pw == band_w_ && distance3(e, band_eye_) <= band_margin_ &&
        distance3(p, band_eye_) <= band_margin_)
        return false;
    const double scale = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    const double steps = opt_.band_steps > 0.0 ? std::max(opt_.band_steps, 1.0) : auto_steps_;
    const double margin = steps * (step * (1.0 + 1e-9) + 1e-12 * scale);
    // Built ahead of the eye, along its last step, as far as keeps the previous eye inside:
    // a camera moving on (an orbit is straight over a few steps) crosses the whole band,
    // about 2 * steps views before the next rebuild instead of steps.
    double c[3] = {e[0], e[1], e[2]};
    if (step > 0.0 && margin > step) {
        const double ahead = 0.999 * (margin - step) / step;
        for (int i = 0; i < 3; ++i) c[i] = e[i] + ahead * (e[i] - p[i]);
    }
    build_band(c, w, margin);
    tune_band_steps(steps);
    return true;
}

// Per frame the band costs about its size, a rebuild about the face count once per 2 * steps
// frames: with a band face costing k faces of a rebuild, the two balance at steps = sqrt(faces /
// (2 k band faces per step)). k is measured with cold caches along an orbit
// (bench/results/finder_targets.md, "the band's auto size").
void SilhouetteFinder::tune_band_steps(double steps) {
    constexpr double kBandFace = 1.25;
    const double per_step = std::max(1.0, double(band_.size()) / steps);
    auto_steps_ = std::clamp(std::sqrt(double(mesh_->face_count()) / (2.0 * kBandFace * per_step)), 2.0, 64.0);
}

// The band's faces now and before: the turned ones listed in turned_ (and their bits set in
// turned_bits_); every other face keeps its facing. Front bits hold the previous view's facing
// of every face (the rebuild's pass sets those outside the band), so only the faces checked need
// theirs set, and those of the band a rebuild's pass left as the float sign at its eye: after a
// rebuild, every band face's.
void SilhouetteFinder::find_turned_faces(Features& out, bool rebuilt) {
    const MeshTopology& mesh = *mesh_;
    turned_.clear();
    check_.clear();
    std::uint64_t* __restrict front = front_bits_.data();
    std::uint64_t* __restrict turned = turned_bits_.data();
    band_.states(filter_, previous_filter_, rebuilt ? front : nullptr, check_);
    const std::size_t nc = check_.size();
    // A face found turned has its record read by reclassify_turned_edges() and its state in a
    // carried full view flipped after (find()): both are fetched as soon as it is found, while the
    // checks go on, so that the misses overlap (bench/results/finder_targets.md).
    const std::uint8_t* carried = out.face_front.size() == mesh.face_count() ? out.face_front.states() : nullptr;
    // Its edges' kinds, written then, too: those of the edges its 64 faces number.
    if (block_edges_begin_.empty()) block_edges_begin_ = first_edges_by_64_faces(mesh);
    const std::uint32_t* eb = block_edges_begin_.size() > 1 ? block_edges_begin_.data() : nullptr;
    constexpr std::size_t kCheckAhead = 8;
    for (std::size_t c = 0; c < nc; ++c) {  // the filters disagree or cannot decide: exact
        if (c + kCheckAhead < nc) {  // (scattered words of both bit sets: their misses overlap)
            const std::uint32_t g = band_.face(check_[c + kCheckAhead]);
            __builtin_prefetch(&front[g >> 6], 1);
            __builtin_prefetch(&turned[g >> 6], 1);
        }
        const std::uint32_t i = check_[c];
        const std::uint32_t f = band_.face(i);
        const MeshTopology::FacingPlane plane = band_.plane(i);
        std::uint8_t now = filter_(plane), before = previous_filter_(plane);
        if (now == FaceFacing::kUnknown)
            now = face_is_front(mesh, f, camera_) ? FaceFacing::kFront : FaceFacing::kBack;
        if (before == FaceFacing::kUnknown)
            before = face_is_front(mesh, f, previous_camera_) ? FaceFacing::kFront : FaceFacing::kBack;
        const std::uint64_t m = std::uint64_t(1) << (f & 63);
        front[f >> 6] = now == FaceFacing::kFront ? (front[f >> 6] | m) : (front[f >> 6] & ~m);
        if (now != before) {
            turned[f >> 6] |= m;
            const auto* r = reinterpret_cast<const char*>(&mesh.face_edges[f]);
            __builtin_prefetch(r);
            __builtin_prefetch(r + sizeof(MeshTopology::FaceEdges) - 1);
            if (carried) __builtin_prefetch(carried + f, 1);
            if (eb) {  // (most of its own edges are among them)
                const std::uint8_t* kinds = out.edge_kind.data();
                const std::uint32_t e0 = eb[f >> 6];
                __builtin_prefetch(kinds + e0, 1);
                __builtin_prefetch(kinds + std::min<std::size_t>(e0 + 64, out.edge_kind.size() - 1), 1);
            }
            turned_.push_back(f);
        }
    }
}

// Edges of turned faces; an edge between two turned faces is decided by the lower one. The
// other face's front bit is this view's (find_turned_faces()). Every edge of a turned face gets
// its kind here. An edge's kind before tells whether it was a previous silhouette edge
// (previous_'s edges are marked: kept by find(), or marked here); one that was and is not is
// dropped_, one that is and was not is fresh_, and the others are unchanged. Turned faces are
// scattered over the mesh: their face records (edges and the faces across them, 24 bytes) and
// most of their edges' kinds were fetched when the checks found them; here the records are
// fetched again 16 faces ahead and the edges' kinds (written) 8 ahead, for what those missed, so
// that the cache misses overlap instead of following each other. Returns the previous edges
// examined again and still silhouettes.
std::size_t SilhouetteFinder::reclassify_turned_edges(Features& out) {
    const MeshTopology& mesh = *mesh_;
    const std::uint64_t* __restrict front = front_bits_.data();
    const std::uint64_t* __restrict turned = turned_bits_.data();
    auto bit = [](const std::uint64_t* bits, std::uint32_t f) { return (bits[f >> 6] >> (f & 63)) & 1; };
    const std::size_t nt = turned_.size();
    std::uint8_t* __restrict kind = out.edge_kind.data();
    if (!marks_kept_)  // the kinds were reset: the previous edges are marked again
        for (std::uint32_t e : previous_) kind[e] = kSil;
    fresh_.clear();
    dropped_.clear();
    std::size_t rechecked = 0;
    const bool seams = !mesh.seam_list.empty();
    constexpr std::size_t kAhead = 8;
    for (std::size_t i = 0; i < nt; ++i) {
        if (i + 2 * kAhead < nt) {
            const auto* r = reinterpret_cast<const char*>(&mesh.face_edges[turned_[i + 2 * kAhead]]);
            __builtin_prefetch(r);
            __builtin_prefetch(r + sizeof(MeshTopology::FaceEdges) - 1);  // (a record may straddle two lines)
        }
        if (i + kAhead < nt)
            for (std::uint32_t e : mesh.face_edges[turned_[i + kAhead]].edge) __builtin_prefetch(&out.edge_kind[e], 1);
        const std::uint32_t x = turned_[i];
        const bool fx = bit(front, x);
        const auto& fe = mesh.face_edges[x];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t e = fe.edge[k], y = fe.face[k];
            if (y == kNoFace || (bit(turned, y) && y < x)) continue;
            ++out.stats.edges_examined;
            const bool sil = (fx != bool(bit(front, y))) != (seams && mesh.is_seam(e));
            const bool was = kind[e] == kSil;
            kind[e] = sil ? kSil : kNoKind;
            if (sil != was) (sil ? fresh_ : dropped_).push_back(e);
            rechecked += sil & was;
        }
    }
    return rechecked;
}

// The silhouette: the previous edges not dropped, and the fresh ones (none of which is a
// previous edge), appended to out.silhouette_edges. In edge order where the previous view's was:
// both lists sorted, and the three merged in one pass over the previous edges' ids.
void SilhouetteFinder::merge_silhouette(Features& out, std::size_t rechecked) {
    const std::size_t np = previous_.size(), nn = fresh_.size(), nd = dropped_.size();
    const std::size_t s0 = out.silhouette_edges.size();
    out.silhouette_edges.resize(s0 + np - nd + nn);
    std::uint32_t* __restrict sil = out.silhouette_edges.data() + s0;
    const std::uint32_t* __restrict prev = previous_.data();
    std::size_t k = 0;
    if (previous_sorted_) {
        sort_edges(fresh_);
        sort_edges(dropped_);
        const std::uint32_t* __restrict add = fresh_.data();
        const std::uint32_t* __restrict drop = dropped_.data();
        std::size_t j = 0, d = 0;
        for (std::size_t i = 0; i < np; ++i) {
            const std::uint32_t r = prev[i];
            if (d < nd && drop[d] == r) {
                ++d;
                continue;
            }
            for (; j < nn && add[j] < r; ++j) sil[k++] = add[j];
            sil[k++] = r;
        }
        for (; j < nn; ++j) sil[k++] = add[j];
    } else {
        const std::uint8_t* kind = out.edge_kind.data();
        for (std::size_t i = 0; i < np; ++i)
            if (kind[prev[i]] == kSil) sil[k++] = prev[i];
        for (std::uint32_t e : fresh_) sil[k++] = e;
    }
    assert(k == np - nd + nn);
    out.stats.edges_examined += np - nd - rechecked;  // the previous edges kept without a look
}

// Edge ids: an LSD radix sort, 11 bits a pass over the bits of the largest edge id (two
// passes up to 4 M edges; the fresh edges of a view are thousands, a comparison sort of them cost
// more than the rest of a coherent view at a degree a frame), std::sort for a few.
void SilhouetteFinder::sort_edges(std::vector<std::uint32_t>& v) {
    std::uint32_t* a = v.data();
    const std::size_t n = v.size();
    if (n < 256) {
        std::sort(a, a + n);
        return;
    }
    constexpr int kBits = 11;
    constexpr std::uint32_t kDigits = 1u << kBits;
    const int bits = std::bit_width(std::uint32_t(std::max<std::size_t>(mesh_->edge_count(), 1) - 1));
    const int passes = std::max(1, (bits + kBits - 1) / kBits);
    radix_tmp_.resize(n);
    std::uint32_t *src = a, *dst = radix_tmp_.data();
    radix_count_.resize(kDigits);
    for (int pass = 0; pass < passes; ++pass) {
        const int shift = pass * kBits;
        std::fill(radix_count_.begin(), radix_count_.end(), 0u);
        std::uint32_t* count = radix_count_.data();
        for (std::size_t i = 0; i < n; ++i) ++count[(src[i] >> shift) & (kDigits - 1)];
        std::uint32_t sum = 0;
        for (std::uint32_t d = 0; d < kDigits; ++d) {
            const std::uint32_t c = count[d];
            count[d] = sum;
            sum += c;
        }
        for (std::size_t i = 0; i < n; ++i) dst[count[(src[i] >> shift) & (kDigits - 1)]++] = src[i];
        std::swap(src, dst);
    }
    if (src != a) std::copy(src, src + n, a);
}

void SilhouetteFinder::search_randomized(const Camera& camera, Features& out, bool carry) {
    const MeshTopology& mesh = *mesh_;
    const std::size_t ne = mesh.edge_count();
    out.stats.fraction = opt_.fraction;
    auto coin = [&](double p) { return p >= 1.0 || double(rng_() >> 11) * 0x1p-53 < p; };

    // Frame coherence first (nothing is marked yet, so what it finds needs no check).
    const bool had_previous = !previous_.empty();
    if (opt_.coherence && had_previous) follow(camera, out);
    // Following a complete silhouette exactly leaves it complete: nothing is left to draw or seek.
    complete_ = complete_ && opt_.coherence && had_previous;
    if (complete_) {
        // follow() listed the edges in edge order, as the exhaustive scan does: then the chains,
        // and the drawing, are those of the exhaustive finder, edge for edge.
        if (carry) {
            out.face_front.carry(camera, turned_.data(), turned_.size());
            carried_ = {&out.face_front, out.face_front.generation()};
        }
        classify_static(mesh, out, [&](std::uint32_t) {});  // crease silhouettes were followed
        previous_.assign(out.silhouette_edges.begin(), out.silhouette_edges.end());
        previous_camera_ = camera;
        previous_filter_ = filter_;
        stamp(out);
        return;
    }

    // Creases and borders are view-independent: classified every view (creases that are
    // silhouettes are traced from).
    classify_static(mesh, out, [&](std::uint32_t e) {
        if (out.edge_kind[e] != kSil) trace(e, out);
    });

    // Seeds on creases and borders: silhouettes often run beside them (cylinders).
    if (opt_.coherence) {
        for (const auto* list : {&mesh.crease_list, &mesh.border_list})
            for (std::uint32_t e : *list)
                if (coin(opt_.seed_fraction))
                    seek(mesh.edge_vertex[e][0], out.face_front[mesh.edge_face[e][0]], camera, out);
    }

    // Random edges, weighted by pi - dihedral angle.
    if (opt_.fraction >= 1.0) {
        for (std::uint32_t e = 0; e < ne; ++e) {
            if (out.edge_kind[e] == kSil) continue;
            ++out.stats.edges_examined;
            if (is_silhouette(mesh, out, e)) trace(e, out);
        }
    } else if (opt_.fraction > 0.0 && ne > 0) {
        if (alias_.size() != ne) build_table();
        // Without a previous view to follow, every drawn edge that misses starts a seek.
        const bool seek_draws = opt_.seek_draws && (!opt_.coherence || !had_previous);
        const auto draws = std::size_t(std::llround(opt_.fraction * double(ne)));
        for (std::size_t i = 0; i < draws; ++i) {
            const std::uint64_t r = rng_();
            const std::uint32_t k = std::uint32_t((std::uint64_t(std::uint32_t(r)) * ne) >> 32);
            const float u = float(r >> 40) * 0x1p-24f;
            const std::uint32_t e = u < alias_prob_[k] ? k : alias_[k];
            if (out.edge_kind[e] == kSil) continue;
            ++out.stats.edges_examined;
            if (is_silhouette(mesh, out, e)) trace(e, out);
            else if (seek_draws) seek(mesh.edge_vertex[e][0], out.face_front[mesh.edge_face[e][0]], camera, out);
        }
    }
    // Only coherence follows the previous view's edges: without it none are kept (no copy a view).
    if (opt_.coherence) {
        previous_.assign(out.silhouette_edges.begin(), out.silhouette_edges.end());
        previous_sorted_ = std::is_sorted(previous_.begin(), previous_.end());
    }
    previous_camera_ = camera;
    previous_filter_ = filter_;
    previous_filter_.bind(mesh, camera);
}

}  // namespace inkline
