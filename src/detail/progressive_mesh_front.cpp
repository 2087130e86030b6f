#include "detail/progressive_mesh_front.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <type_traits>

#include <glm/geometric.hpp>

namespace inkline {

AreaUnits AreaUnits::for_input(const PmInput& in) {
    AreaUnits u;
    if (in.positions.empty()) return u;
    glm::dvec3 lo = in.positions[0], hi = lo;
    for (const glm::dvec3& p : in.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const double d2 = glm::dot(hi - lo, hi - lo);
    const double unit = double(std::max<std::size_t>(in.triangles.size(), 1)) * d2 * 0x1p-63;
    if (unit > 0.0 && std::isfinite(unit)) u = {unit, 1.0 / unit};
    return u;
}

AdaptiveFront::AdaptiveFront(const ProgressiveMesh& pm, GeomorphOptions geomorphs)
    : pm_(pm), geomorphs_(geomorphs), units_(AreaUnits::for_input(pm.input())) {
    const PmInput in = pm.input();
    const std::size_t n = in.positions.size(), faces = in.triangles.size(), m = pm.collapses();
    // (the slot words give up one bit, so indices must stay below 2^31: 2 billion vertices)
    std::vector<std::uint32_t> collapse(n, none), pending(n, 0);
    for (std::size_t i = 0; i < m; ++i) {
        collapse[pm.removed_vertex()[i]] = std::uint32_t(i);
        ++pending[pm.kept_vertex()[i]];
    }
    made_.assign(m, Made{none, none, {none, none}});
    changed_in_frame_.assign(m, 0);
    // The front starts as the input: every vertex in a face, in input order.
    vertex_slot_.assign(n, tag | index_mask);
    vert_.reserve(n);
    front_data_.reserve(n);
    front_id_.reserve(n);
    for (const auto& t : in.triangles)
        for (const std::uint32_t v : t) vertex_slot_[v] = 0;
    for (std::uint32_t v = 0; v < n; ++v)
        if (vertex_slot_[v] == 0) front_add(v, collapse[v], none, pending[v]);
    face_slot_.assign(faces, none);
    faces_.reserve(faces);
    face_id_.reserve(faces);
    for (std::size_t f = 0; f < faces; ++f) add_face(std::uint32_t(f));
    for (const Vertex& v : vert_) refresh_ring_area(v.id);
}

std::uint32_t AdaptiveFront::collapse_of(std::uint32_t v) const {
    if (active(v)) return rec(v).collapse_of;
    const std::uint32_t i = vertex_slot_[v] & index_mask;
    return i == index_mask ? none : i;
}

bool AdaptiveFront::at_bottom(std::uint32_t v) const {
    if (active(v)) return rec(v).last_collapse == none;
    const std::uint32_t i = collapse_of(v);
    return i == none || made_[i].removed_stack == none;
}

std::uint32_t AdaptiveFront::parent(std::uint32_t v) const { return pm_.kept_vertex()[collapse_of(v)]; }

std::uint32_t AdaptiveFront::representative(std::uint32_t u) const {
    while (!active(u)) u = pm_.kept_vertex()[vertex_slot_[u] & index_mask];
    return u;
}

// (a corner linked to v adds its face's area to v's ring sum; unlinked, takes it away)
void AdaptiveFront::link(std::uint32_t c, std::uint32_t v) {
    const std::uint32_t s = vertex_slot_[v];
    Vertex& x = vert_[s];
    corner_vertex(c) = v;
    next_corner(c) = x.head;
    x.head = c;
    ring_[s].sum += faces_[face_of(c)].area;
    ++ring_[s].faces;
}

void AdaptiveFront::unlink(std::uint32_t c) {
    const std::uint32_t s = vertex_slot_[corner_vertex(c)];
    std::uint32_t* at = &vert_[s].head;
    while (*at != c) at = &next_corner(*at);
    *at = next_corner(c);
    ring_[s].sum -= faces_[face_of(c)].area;
    --ring_[s].faces;
}

// A hole of the pool near `slot` (a few pages either side; in its own 64 slots the nearest), or
// none: a record placed there shares cache lines and pages with its ring neighbours' records.
std::uint32_t AdaptiveFront::Holes::near(std::uint32_t slot) const {
    constexpr std::size_t reach = 4;  // words each side: about 300 slots, 10 KiB of 32-byte records
    const std::size_t w0 = slot / 64;
    if (count == 0 || w0 >= bits.size()) return none;
    const std::uint32_t b = slot % 64;
    if (const std::uint64_t here = bits[w0]) {
        const std::uint64_t below = here & (b == 63 ? ~std::uint64_t(0) : (std::uint64_t(2) << b) - 1), above = here & ~below;
        const int lo = below ? 63 - std::countl_zero(below) : -1, hi = above ? std::countr_zero(above) : -1;
        const int at = lo < 0 ? hi : hi < 0 ? lo : (int(b) - lo <= hi - int(b) ? lo : hi);
        return std::uint32_t(64 * w0 + std::size_t(at));
    }
    for (std::size_t d = 1; d <= reach; ++d) {
        if (w0 >= d && bits[w0 - d]) return std::uint32_t(64 * (w0 - d) + std::size_t(63 - std::countl_zero(bits[w0 - d])));
        if (w0 + d < bits.size() && bits[w0 + d]) return std::uint32_t(64 * (w0 + d) + std::size_t(std::countr_zero(bits[w0 + d])));
    }
    return none;
}

// A slot for input face f (a hole near `near_slot` when there is one, else a new slot at the
// pool's end), its corners the current representatives of the input's, linked into their
// vertices' lists in corner order.
std::uint32_t AdaptiveFront::add_face(std::uint32_t f, std::uint32_t near_slot) {
    std::uint32_t s = near_slot == none ? none : face_holes_.near(near_slot);
    if (s != none) {
        face_holes_.take(s);
        face_id_[s] = f;
    } else {
        s = std::uint32_t(faces_.size());
        if (faces_.size() == faces_.capacity()) {  // (by a quarter, never past the input's faces)
            const std::size_t capacity = std::min(faces_.size() + faces_.size() / 4 + 64, face_slot_.size());
            faces_.reserve(capacity);
            face_id_.reserve(capacity);
        }
        faces_.push_back(Face{{none, none, none}, {none, none, none}, 0});
        face_id_.push_back(f);
        face_holes_.grow(faces_.size());
        face_holes_.misplaced += near_slot != none;
    }
    face_slot_[f] = s;
    const auto& tri = pm_.input().triangles[f];
    for (int j = 0; j < 3; ++j) faces_[s].vertex[j] = representative(tri[j]);
    faces_[s].area = face_area(s);  // (before its corners are linked: linking adds it to their sums)
    for (std::uint32_t c = 4 * s; c < 4 * s + 3; ++c) link(c, corner_vertex(c));
    ++active_face_count_;
    return s;
}

void AdaptiveFront::remove_face(std::uint32_t s) {
    for (std::uint32_t c = 4 * s; c < 4 * s + 3; ++c) unlink(c);
    face_slot_[face_id_[s]] = none;
    face_id_[s] = none;
    face_holes_.free(s);
    --active_face_count_;
}

// The pools laid out again, the live records in the pool's order (a compaction over the holes)
// or in the input's (spatially coherent: once many records had no hole near their neighbours'
// and went to the pool's end), with a hole after every `gap_every` records so that a split's
// records find one near their neighbours'. The face pool's corner links and the vertices' heads
// are renumbered, the input's slots set; the front's order is kept (front_id_ holds input ids).
void AdaptiveFront::relay_faces(bool input_order) {
    std::vector<std::uint32_t> order;  // the live records' slots in their new order (rare: not kept)
    if (input_order) {
        for (const std::uint32_t s : face_slot_)
            if (s != none) order.push_back(s);
    } else {
        for (std::uint32_t s = 0; s < faces_.size(); ++s)
            if (face_id_[s] != none) order.push_back(s);
    }
    const std::size_t live = order.size(), size = live + live / gap_every, capacity = size + size / 4 + 64;
    std::vector<Face> faces;
    std::vector<std::uint32_t> ids, to(faces_.size(), none);
    faces.reserve(capacity);
    ids.reserve(capacity);
    face_holes_ = Holes{};
    face_holes_.grow(size);
    for (std::size_t j = 0; j < live; ++j) {
        if (j > 0 && j % gap_every == 0) {
            face_holes_.free(std::uint32_t(faces.size()));
            faces.push_back(Face{{none, none, none}, {none, none, none}, 0});
            ids.push_back(none);
        }
        to[order[j]] = std::uint32_t(faces.size());
        face_slot_[face_id_[order[j]]] = std::uint32_t(faces.size());
        faces.push_back(faces_[order[j]]);
        ids.push_back(face_id_[order[j]]);
    }
    const auto moved = [&](std::uint32_t c) { return c == none ? none : 4 * to[face_of(c)] + slot_of(c); };
    for (Face& f : faces)
        for (std::uint32_t& c : f.next) c = moved(c);
    for (Vertex& v : vert_) v.head = moved(v.head);  // (a hole's head is none)
    faces_.swap(faces);
    face_id_.swap(ids);
}

void AdaptiveFront::relay_vertices(bool input_order) {
    std::vector<std::uint32_t> order;  // the live records' slots in their new order (rare: not kept)
    if (input_order) {
        for (std::uint32_t v = 0; v < vertex_slot_.size(); ++v)
            if (active(v)) order.push_back(vertex_slot_[v]);
    } else {
        for (std::uint32_t s = 0; s < vert_.size(); ++s)
            if (!vert_holes_.is_free(s)) order.push_back(s);
    }
    const std::size_t live = order.size(), size = live + live / gap_every, capacity = size + size / 4 + 64;
    std::vector<Vertex> records;
    std::vector<glm::vec4> data;
    std::vector<RingSum> rings;
    records.reserve(capacity);
    data.reserve(capacity);
    rings.reserve(capacity);
    vert_holes_ = Holes{};
    vert_holes_.grow(size);
    for (std::size_t j = 0; j < live; ++j) {
        if (j > 0 && j % gap_every == 0) {
            vert_holes_.free(std::uint32_t(records.size()));
            records.push_back(Vertex{none, none, none, none, 0, 0, none, 0, 0, 0});
            data.push_back(glm::vec4(0.0f, 0.0f, 0.0f, std::numeric_limits<float>::quiet_NaN()));
            rings.push_back(RingSum{0, 0, 0});
        }
        vertex_slot_[vert_[order[j]].id] = std::uint32_t(records.size());
        records.push_back(vert_[order[j]]);
        data.push_back(front_data_[order[j]]);
        rings.push_back(ring_[order[j]]);
    }
    vert_.swap(records);
    front_data_.swap(data);
    ring_.swap(rings);
}

// A pool a fifth holes is compacted, one an eighth out of place laid out in the input's order
// again (amortized: only after that many operations). A layout moves every live record and mends
// every corner link: 1.2-2.3 ms for 40-95 k faces on bunny00@2's dolly, as much as 250-450
// operations, so it is the frame's first work and a budgeted frame's budget pays for it (a layout
// at a frame's end made the worst frames, 1.3-1.5 ms above their neighbours). Its cost: a record
// moved about 1/256 of an operation, an input slot scanned for the input's order 1/2048.
std::size_t AdaptiveFront::lay_out_pools() {
    constexpr std::size_t slack = 1024, records_per_operation = 256, slots_per_operation = 2048;
    const std::size_t front = front_id_.size();
    std::size_t moved = 0, scanned = 0;
    if (face_holes_.misplaced > active_face_count_ / 8 + slack) {
        moved += active_face_count_, scanned += face_slot_.size();
        relay_faces(true);
    } else if (face_holes_.count > active_face_count_ / 4 + slack) {
        moved += active_face_count_;
        relay_faces(false);
    }
    if (vert_holes_.misplaced > front / 8 + slack) {
        moved += front, scanned += vertex_slot_.size();
        relay_vertices(true);
    } else if (vert_holes_.count > front / 4 + slack) {
        moved += front;
        relay_vertices(false);
    }
    return moved / records_per_operation + scanned / slots_per_operation;
}

// Storage follows the front: vertex and worklist storage far beyond the front's size (after a
// coarsening, e.g. the first frame from the input) is given back. The pools grow and are refitted
// by a quarter, so a growing or shrinking front reallocates geometrically.
void AdaptiveFront::trim_storage() {
    const std::size_t slack = 1024, front = front_id_.size();
    const auto refit = [](auto& v, std::size_t capacity) {
        std::remove_reference_t<decltype(v)> kept;
        kept.reserve(capacity);
        kept.assign(v.begin(), v.end());
        v.swap(kept);
    };
    const std::size_t n = vert_.size();
    if (vert_.capacity() > n + n / 2 + slack) {
        refit(vert_, n + n / 4);
        refit(front_data_, n + n / 4);
        refit(ring_, n + n / 4);
    }
    if (front_id_.capacity() > front + front / 2 + slack) refit(front_id_, front + front / 4);
    if (work_.capacity() > 2 * n + slack) refit(work_, n);  // (empty between frames)
    if (found_.capacity() > 2 * n + slack) refit(found_, n);  // (empty between frames too)
    if (ranked_.capacity() > 2 * n + slack) refit(ranked_, n);  // (empty between frames too)
    // (the first frame from the input with geomorphs starts a collapse at most vertices)
    if (morphs_.capacity() > 2 * morphs_.size() + 4 * slack) refit(morphs_, 2 * morphs_.size() + slack);
}

// v joins the front (at its end) with a record in a hole near `near_slot` (its parent's record)
// when there is one, else in a new slot at the pool's end.
void AdaptiveFront::front_add(std::uint32_t v, std::uint32_t collapse, std::uint32_t last_collapse,
                              std::uint32_t pending, std::uint32_t near_slot) {
    const Vertex x{v, none, collapse, last_collapse, pending, 0, std::uint32_t(front_id_.size()), 0, 0, 0};
    const glm::vec4 data(glm::vec3(pm_.input().positions[v]), 0.0f);  // (area: refresh_ring_area)
    std::uint32_t s = near_slot == none ? none : vert_holes_.near(near_slot);
    if (s != none) {
        vert_holes_.take(s);
        vert_[s] = x;
        front_data_[s] = data;
        ring_[s] = RingSum{0, 0, 0};
    } else {
        s = std::uint32_t(vert_.size());
        if (vert_.size() == vert_.capacity()) {  // (by a quarter, never past the input's vertices)
            const std::size_t capacity = std::min(vert_.size() + vert_.size() / 4 + 64, vertex_slot_.size());
            vert_.reserve(capacity);
            front_data_.reserve(capacity);
            ring_.reserve(capacity);
        }
        vert_.push_back(x);
        front_data_.push_back(data);
        ring_.push_back(RingSum{0, 0, 0});
        vert_holes_.grow(vert_.size());
        vert_holes_.misplaced += near_slot != none;
    }
    vertex_slot_[v] = s;
    front_id_.push_back(v);
}

// v leaves the front, removed by collapse i: its record becomes a hole (its area NaN, which no
// band test passes) and the front's last vertex takes its place in the front's order; its stack
// waits in made_[i].
void AdaptiveFront::front_remove(std::uint32_t v, std::uint32_t i) {
    const std::uint32_t s = vertex_slot_[v], at = vert_[s].front_at, last = front_id_.back();
    made_[i].removed_stack = vert_[s].last_collapse;
    front_id_[at] = last;
    rec(last).front_at = at;
    front_id_.pop_back();
    vert_[s].id = vert_[s].head = none;
    front_data_[s].w = std::numeric_limits<float>::quiet_NaN();
    vert_holes_.free(s);
    vertex_slot_[v] = tag | i;
}

std::int64_t AdaptiveFront::face_area(std::uint32_t f) const {
    const auto& p = pm_.input().positions;
    const glm::dvec3 a = p[face_vertex(f, 0)], b = p[face_vertex(f, 1)], c = p[face_vertex(f, 2)];
    return units_.of(0.5 * glm::length(glm::cross(b - a, c - a)));
}

// A face whose corner moved: its area again, the change added to its corners' ring sums (the
// face is linked into each corner's list).
void AdaptiveFront::refresh_face_area(std::uint32_t f) {
    const std::int64_t area = face_area(f), change = area - faces_[f].area;
    faces_[f].area = area;
    if (change != 0)
        for (int j = 0; j < 3; ++j) ring_[vertex_slot_[face_vertex(f, j)]].sum += change;
}

void AdaptiveFront::refresh_ring_area(std::uint32_t v) {
    if (!active(v)) return;
    const RingSum& x = ring_[vertex_slot_[v]];
    front_data_[vertex_slot_[v]].w = units_.mean(x.sum, x.faces);
}

std::size_t AdaptiveFront::ring_sums_differing() const {
    std::size_t differing = 0;
    for (const std::uint32_t v : front_id_) {
        std::int64_t sum = 0;
        std::uint32_t faces = 0;
        for (std::uint32_t c = rec(v).head; c != none; c = next_corner(c), ++faces) sum += face_area(face_of(c));
        const RingSum& x = ring_[vertex_slot_[v]];
        differing += x.sum != sum || x.faces != faces || front_data_[vertex_slot_[v]].w != units_.mean(sum, faces);
    }
    return differing;
}

void AdaptiveFront::neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) const {
    out.clear();
    for (std::uint32_t c = rec(v).head; c != none; c = next_corner(c))
        for (int j = 0; j < 3; ++j) {
            const std::uint32_t u = face_vertex(face_of(c), j);
            if (u != v && std::find(out.begin(), out.end(), u) == out.end()) out.push_back(u);
        }
}

double AdaptiveFront::scale(std::uint32_t v) const {
    const glm::dvec3& p = pm_.input().positions[v];
    return inkline::image_area(*camera_, 1.0, camera_->depth(p));
}

double AdaptiveFront::target(std::uint32_t v) const { return criterion_->target_at(*camera_, pm_.input().positions[v]); }

double AdaptiveFront::image_area_of(std::uint32_t v, const Camera& camera) const {
    return inkline::image_area(camera, ring_area(v), camera.depth(pm_.input().positions[v]));
}

void AdaptiveFront::enqueue(std::uint32_t v) {
    if (rec(v).queued == frame16()) return;
    rec(v).queued = frame16();
    work_.push_back(v);
}

bool AdaptiveFront::dequeue(std::uint32_t v) {
    if (!active(v)) return false;
    Vertex& x = rec(v);
    x.queued = 0;
    return x.head != none;
}

// A change of v's ring may lift what refused it: it is tried again from now on, and so are the
// neighbours whose collapse onto v its ring (the link condition) refused, unless v is locked.
void AdaptiveFront::enqueue_changed(std::uint32_t v) {
    Vertex& x = rec(v);
    x.retry_at = 0;
    if (x.locked) return;  // (a locked vertex is found by the scan once its morph ends)
    enqueue(v);
    if (x.waited_on) wake_around(v);
}

// A geomorph's lock on v ends; if it was the last, the neighbours waiting on it are tried again.
void AdaptiveFront::unlock(std::uint32_t v) {
    Vertex& x = rec(v);
    --x.locked;
    if (!x.locked && x.waited_on) wake_around(v);
}

// v is free and its neighbours waited on it (Vertex::waited_on): its refused neighbours (those that
// waited on it among them) are tried again.
void AdaptiveFront::wake_around(std::uint32_t v) {
    rec(v).waited_on = 0;
    for (std::uint32_t c = rec(v).head; c != none; c = next_corner(c))
        for (int j = 0; j < 3; ++j) {
            const std::uint32_t u = face_vertex(face_of(c), j);
            if (rec(u).retry_at > frame_) {
                rec(u).retry_at = 0;
                if (!rec(u).locked) enqueue(u);
            }
        }
}

bool AdaptiveFront::refuse(std::uint32_t v, std::uint32_t frames) {
    rec(v).retry_at = frame_ + frames;
    return false;
}

// u put in its place in a sorted ring unless there already. (Insertion: a ring is a dozen
// entries, where std::sort and unique cost several times as much.)
static void insert_sorted(std::vector<std::uint32_t>& ring, std::uint32_t u) {
    std::size_t at = ring.size();
    while (at > 0 && ring[at - 1] > u) --at;
    if (at > 0 && ring[at - 1] == u) return;
    ring.insert(ring.begin() + std::ptrdiff_t(at), u);
}

// v's neighbours, sorted and each once; returns v's face count. (In a manifold a vertex is on the
// border exactly when it has more neighbours than faces: an open fan.)
std::size_t AdaptiveFront::sorted_ring(std::uint32_t v, std::vector<std::uint32_t>& out) const {
    out.clear();
    std::size_t faces = 0;
    for (std::uint32_t c = rec(v).head; c != none; c = next_corner(c), ++faces) {
        const Face& f = faces_[face_of(c)];
        const std::uint32_t j = slot_of(c);
        insert_sorted(out, f.vertex[(j + 1) % 3]);
        insert_sorted(out, f.vertex[(j + 2) % 3]);
    }
    return faces;
}

// The link condition (the common neighbours of r and k are exactly the third corners of the faces
// on edge rk), no interior edge between two border vertices, and k keeps at least 3 neighbours.
// The rings are small sorted arrays, so their common part is one merge.
bool AdaptiveFront::collapse_ok(std::uint32_t r, std::uint32_t k) {
    // (r's ring listed sorted in the same walk that finds the faces on edge rk and their third corners)
    std::uint32_t wings[2] = {none, none};
    int shared = 0;
    std::size_t faces_r = 0;
    ring_r_.clear();
    for (std::uint32_t c = rec(r).head; c != none; c = next_corner(c), ++faces_r) {
        const Face& f = faces_[face_of(c)];
        const std::uint32_t j = slot_of(c), a = f.vertex[(j + 1) % 3], b = f.vertex[(j + 2) % 3];
        insert_sorted(ring_r_, a);
        insert_sorted(ring_r_, b);
        if (a != k && b != k) continue;
        if (shared == 2) return false;
        wings[shared++] = a == k ? b : a;
    }
    if (shared == 0 || (shared == 2 && wings[0] == wings[1])) return false;
    const std::size_t faces_k = sorted_ring(k, ring_k_);
    std::size_t common = 0;
    for (std::size_t a = 0, b = 0; a < ring_r_.size() && b < ring_k_.size();) {
        if (ring_r_[a] < ring_k_[b]) {
            ++a;
        } else if (ring_k_[b] < ring_r_[a]) {
            ++b;
        } else {  // (neither ring holds its own vertex, so k and r never meet here)
            if (ring_r_[a] != wings[0] && ring_r_[a] != wings[1]) return false;
            ++common, ++a, ++b;
        }
    }
    if (common != std::size_t(shared)) return false;
    if (ring_r_.size() + ring_k_.size() - 2 - common < 3) return false;
    // An interior edge rk (two faces) between two border vertices would pinch the surface.
    return !(shared == 2 && ring_r_.size() > faces_r && ring_k_.size() > faces_k);
}

// Whether a face of r's ring would turn over (or become degenerate) when r moves onto k; if none
// does, r's ring faces are listed (pool slots, in r's list order) with their areas after the
// collapse: -1 on edge rk (removed), else the moved face's (the value refresh_face_area would
// give: half its normal's length, the normal the flip test computed). Listed once a collapse's
// band guard, which reads each of them from two or three rings.
bool AdaptiveFront::flips_else_list_faces(std::uint32_t r, std::uint32_t k) {
    const auto& p = pm_.input().positions;
    r_faces_.clear();
    r_areas_.clear();
    for (std::uint32_t c = rec(r).head; c != none; c = next_corner(c)) {
        const std::uint32_t f = face_of(c);
        glm::dvec3 before[3], after[3];
        bool has_k = false;
        for (int j = 0; j < 3; ++j) {
            const std::uint32_t u = face_vertex(f, j);
            has_k |= u == k;
            before[j] = p[u];
            after[j] = p[u == r ? k : u];
        }
        r_faces_.push_back(f);
        if (has_k) {
            r_areas_.push_back(-1);
            continue;
        }
        const glm::dvec3 n0 = glm::cross(before[1] - before[0], before[2] - before[0]);
        const glm::dvec3 n1 = glm::cross(after[1] - after[0], after[2] - after[0]);
        if (!(glm::dot(n0, n1) > 0.0)) return true;
        r_areas_.push_back(units_.of(0.5 * glm::length(n1)));
    }
    return false;
}

// What refresh_ring_area would store for u (r's neighbour, k among them) after raw_collapse(r) onto
// k: u's kept sum with the changes of r's faces that hold u (the faces on edge rk removed, the
// others moved: flips_else_list_faces's areas), and for k r's moved faces added. Integer sums, so
// the guard decides exactly as if it had collapsed and measured, without walking u's ring.
float AdaptiveFront::ring_area_after_collapse(std::uint32_t u, std::uint32_t k) const {
    const RingSum& x = ring_[vertex_slot_[u]];
    std::int64_t sum = x.sum;
    std::uint32_t faces = x.faces;
    for (std::size_t j = 0; j < r_faces_.size(); ++j) {
        const Face& f = faces_[r_faces_[j]];
        const bool holds_u = f.vertex[0] == u || f.vertex[1] == u || f.vertex[2] == u;
        if (r_areas_[j] < 0) {  // (on edge rk: removed; k holds it too)
            if (holds_u) sum -= f.area, --faces;
        } else if (holds_u) {
            sum += r_areas_[j] - f.area;
        } else if (u == k) {
            sum += r_areas_[j], ++faces;
        }
    }
    return units_.mean(sum, faces);
}

void AdaptiveFront::raw_collapse(std::uint32_t r) {
    const std::uint32_t i = rec(r).collapse_of, k = parent(r);
    std::array<std::uint32_t, 2> dead{none, none};  // (pool slots, then input faces)
    int n_dead = 0;
    for (std::uint32_t c = rec(r).head; c != none; c = next_corner(c)) {
        const std::uint32_t f = face_of(c);
        if (face_vertex(f, 0) == k || face_vertex(f, 1) == k || face_vertex(f, 2) == k) dead[n_dead++] = f;
    }
    for (std::uint32_t& f : dead)
        if (f != none) {
            const std::uint32_t slot = f;
            f = face_id_[slot];
            remove_face(slot);
        }
    while (rec(r).head != none) {  // (its area moves to k's sum, then changes in its corners' sums)
        const std::uint32_t c = rec(r).head;
        unlink(c);
        link(c, k);
        refresh_face_area(face_of(c));
    }
    front_remove(r, i);
    made_[i].dead = dead;
    made_[i].prev = rec(k).last_collapse;
    rec(k).last_collapse = i;
    --rec(k).pending_children;
}

// The latest collapse made onto k can be undone when each face it removed finds its third corner
// among k's neighbours (the faces around it were refined or coarsened since, but not across it).
bool AdaptiveFront::split_ok(std::uint32_t k) const {
    const std::uint32_t i = rec(k).last_collapse;
    if (i == none) return false;
    const std::uint32_t r = pm_.removed_vertex()[i];
    const auto& tri = pm_.input().triangles;
    for (std::uint32_t f : made_[i].dead) {
        if (f == none) continue;
        int at_r = 0, at_k = 0;
        std::uint32_t third = none;
        for (int j = 0; j < 3; ++j) {
            std::uint32_t u = tri[f][j];
            while (u != r && !active(u)) u = parent(u);
            if (u == r)
                ++at_r;
            else if (u == k)
                ++at_k;
            else
                third = u;
        }
        if (at_r != 1 || at_k != 1 || third == none) return false;
        bool adjacent = false;
        for (std::uint32_t c = rec(k).head; c != none && !adjacent; c = next_corner(c))
            for (int j = 0; j < 3; ++j) adjacent |= face_vertex(face_of(c), j) == third;
        if (!adjacent) return false;
    }
    return true;
}

// v's ring faces (v, a, b), read as edges a -> b, chain into one cycle (inside) or one path (on
// the border), each a and each b once: a manifold, consistently oriented neighbourhood.
bool AdaptiveFront::ring_is_disk(std::uint32_t v) const {
    std::uint32_t from[64], to[64];
    std::size_t n = 0;
    for (std::uint32_t c = rec(v).head; c != none; c = next_corner(c)) {
        if (n == 64) return false;
        const std::uint32_t f = face_of(c), j = slot_of(c);
        from[n] = face_vertex(f, (j + 1) % 3);
        to[n] = face_vertex(f, (j + 2) % 3);
        ++n;
    }
    if (n == 0) return true;
    std::size_t starts = 0;  // edges whose `from` is no edge's `to`: the path's start on a border
    std::size_t start = 0;
    for (std::size_t a = 0; a < n; ++a) {
        int as_from = 0, as_to = 0;
        for (std::size_t b = 0; b < n; ++b) {
            as_from += from[b] == from[a];
            as_to += to[b] == from[a];
        }
        if (as_from != 1 || as_to > 1) return false;
        if (as_to == 0) {
            ++starts;
            start = a;
        }
    }
    if (starts > 1) return false;
    std::size_t walked = 1;  // follow the chain from its start: it must visit every edge
    for (std::size_t e = start; walked <= n; ++walked) {
        std::size_t next = n;
        for (std::size_t b = 0; b < n; ++b)
            if (from[b] == to[e]) next = b;
        if (next == n || next == start) break;
        e = next;
    }
    return walked == n;
}

std::uint32_t AdaptiveFront::raw_split(std::uint32_t k) {
    const std::uint32_t i = rec(k).last_collapse, r = pm_.removed_vertex()[i];
    const auto& tri = pm_.input().triangles;
    rec(k).last_collapse = made_[i].prev;
    made_[i].prev = none;
    ++rec(k).pending_children;
    const std::uint32_t near_face = rec(k).head == none ? none : face_of(rec(k).head);
    // (every collapse onto r was made: tree order; r's record goes near k's)
    front_add(r, i, made_[i].removed_stack, 0, vertex_slot_[k]);
    made_[i].removed_stack = none;
    for (std::uint32_t c = rec(k).head, next = none; c != none; c = next) {
        next = next_corner(c);
        if (representative(tri[face_id_[face_of(c)]][slot_of(c)]) == r) {
            unlink(c);
            link(c, r);
            refresh_face_area(face_of(c));
        }
    }
    for (std::uint32_t f : made_[i].dead)
        if (f != none) add_face(f, near_face);
    made_[i].dead = {none, none};
    return r;
}

// Every vertex whose ring changed gets its area again, also one queued already (it is tried with
// the new ring, and the next frame's scan reads it).
void AdaptiveFront::touch_ring(std::uint32_t v) {
    refresh_ring_area(v);
    enqueue_changed(v);
    neighbours(v, touched_);
    for (const std::uint32_t u : touched_) {
        refresh_ring_area(u);
        enqueue_changed(u);
    }
}

// r collapses onto k. The rings that change are r's neighbours' (k among them: r's faces move to
// k or go), so only their sums changed; k's other neighbours keep their rings and areas (a
// refusal of theirs that k's ring decided is woken through k's waited_on).
void AdaptiveFront::collapse_made(std::uint32_t r) {
    raw_collapse(r);
    for (const std::uint32_t u : ring_r_) {
        refresh_ring_area(u);
        enqueue_changed(u);
    }
}

bool AdaptiveFront::try_collapse(std::uint32_t r) {
    const std::uint32_t i = rec(r).collapse_of;
    if (i == none || rec(r).locked || changed_in_frame_[i] == frame16()) return false;
    const std::uint32_t k = parent(r);
    const double t_r = target(r);
    if (!(t_r > 0.0) || !(image_area(r) < criterion_->collapse * t_r)) return false;
    // Refusals that only a change of r's ring (or k's lock ending, or k's ring changing) can lift
    // stamp r: the scan then skips it until enqueue_changed or wake_around clears the stamp (or, a
    // backstop, a few frames pass). The criterion's refusals (the band guard) are not stamped: the
    // camera moves them.
    if (active(k) && rec(k).locked) {  // (k's unlock wakes r)
        rec(k).waited_on = 1;
        return refuse(r, lock_backstop_frames);
    }
    // Hoppe's tree order: r goes only with its whole subtree (every collapse onto it made first).
    if (!active(k) || rec(r).pending_children != 0) return refuse(r, retry_frames);
    if (!collapse_ok(r, k)) {  // (the link condition reads k's ring too: a change of it wakes r)
        rec(k).waited_on = 1;
        return refuse(r, retry_frames);
    }
    if (flips_else_list_faces(r, k)) return refuse(r, retry_frames);
    // The band guard: no vertex of the changed rings (r's neighbours, k among them) may end above
    // t_s T unless it was there and does not grow; measured without making the collapse. (Not
    // stamped: the band moves with the camera, so it is tried again next frame.)
    for (const std::uint32_t u : ring_r_) {
        const double after = scale(u) * ring_area_after_collapse(u, k);
        if (!(after <= std::max(criterion_->split * target(u), image_area(u)))) return false;
    }
    if (geomorphs_.enabled) {
        // (ring_r_ holds r's neighbours from collapse_ok: lock_ring's, in another order)
        ++rec(r).locked;
        for (const std::uint32_t u : ring_r_) ++rec(u).locked;
        const double speed = std::clamp(criterion_->collapse * t_r / image_area(r), 1.0, geomorphs_.max_speedup);
        const auto& p = pm_.input().positions;
        morphs_.push_back({r, k, true, ring_area(r), 0.0, speed / std::max(geomorphs_.seconds, 1e-9), p[r], p[k]});
        ++stats_->morphs_started;
        return true;
    }
    changed_in_frame_[i] = frame16();
    collapse_made(r);  // (ring_r_: r's ring, from collapse_ok)
    ++stats_->collapses;
    return true;
}

bool AdaptiveFront::try_split(std::uint32_t k) {
    const std::uint32_t i = rec(k).last_collapse;
    if (rec(k).locked || i == none || changed_in_frame_[i] == frame16()) return false;
    const double t_k = target(k), a = image_area(k);
    if (!(a > criterion_->split * t_k) || !split_ok(k)) return false;
    const std::uint32_t r = raw_split(k);
    refresh_ring_area(r);
    refresh_ring_area(k);
    // The split's guards: the changed rings are disks (the neighbourhood may have changed since
    // the collapse), and neither child falls below t_c T (it would be collapsed straight back).
    bool disks = ring_is_disk(r) && ring_is_disk(k);
    neighbours(r, ring_r_);
    for (std::size_t j = 0; j < ring_r_.size() && disks; ++j) disks = ring_is_disk(ring_r_[j]);
    if (!disks || image_area(r) < criterion_->collapse * target(r) || image_area(k) < criterion_->collapse * t_k) {
        raw_collapse(r);
        refresh_ring_area(k);
        return false;
    }
    changed_in_frame_[i] = frame16();
    touch_ring(r);
    touch_ring(k);
    ++stats_->splits;
    if (geomorphs_.enabled) {
        ++rec(r).locked;
        ++rec(k).locked;
        const double speed = t_k > 0.0 ? std::clamp(a / (criterion_->split * t_k), 1.0, geomorphs_.max_speedup)
                                        : geomorphs_.max_speedup;
        const auto& p = pm_.input().positions;
        morphs_.push_back({r, k, false, 0.0f, 0.0, speed / std::max(geomorphs_.seconds, 1e-9), p[k], p[r]});
        ++stats_->morphs_started;
    }
    return true;
}

// A collapse in flight locks r and its whole ring (k among it): no other operation may change the
// ring, so the collapse stays legal until it is made.
void AdaptiveFront::lock_ring(std::uint32_t r, int delta) {
    rec(r).locked = std::uint16_t(rec(r).locked + delta);
    neighbours(r, ring_r_);
    for (std::uint32_t u : ring_r_) rec(u).locked = std::uint16_t(rec(u).locked + delta);
}

void AdaptiveFront::advance_morphs(double frame_seconds) {
    for (std::size_t j = 0; j < morphs_.size();) {
        Morph& m = morphs_[j];
        const std::uint32_t r = m.vertex, k = m.parent;
        if (m.collapse) {  // faster the further r has fallen below the band meanwhile
            // (target(r) and image_area(r) from the morph's record: m.from is r's position)
            const double t_r = criterion_->target_at(*camera_, m.from);
            const double a = inkline::image_area(*camera_, 1.0, camera_->depth(m.from)) * m.ring_area;
            if (t_r > 0.0 && a > 0.0)
                m.speed = std::max(m.speed, std::clamp(criterion_->collapse * t_r / a, 1.0, geomorphs_.max_speedup) /
                                                std::max(geomorphs_.seconds, 1e-9));
        }
        const glm::dvec3 was = shown(m);
        m.progress = std::min(1.0, m.progress + m.speed * frame_seconds);
        const glm::dvec3 now = shown(m);
        if (camera_->depth(was) > 0.0 && camera_->depth(now) > 0.0)
            stats_->largest_move_px =
                std::max(stats_->largest_move_px, glm::length(camera_->project(now) - camera_->project(was)));
        if (m.progress < 1.0) {
            ++j;
            continue;
        }
        ++stats_->morphs_ended;
        if (m.collapse) {
            lock_ring(r, -1);
            collapse_made(r);  // (ring_r_: r's ring, from lock_ring)
            ++stats_->collapses;
        } else {
            unlock(r);
            unlock(k);
        }
        m = morphs_.back();
        morphs_.pop_back();
    }
}

// A budgeted frame takes the most visible errors first: the scan's candidates by their
// discrepancy, largest first (ties by vertex, so the order is the same on every run). Sorted a
// chunk at a time as the drain reaches it (from `from`, twice the operations left: some are
// refused), so a backlog of deferred candidates costs a linear selection a frame, not a sort.
// Returns the chunk's end.
std::size_t AdaptiveFront::rank_next(std::size_t from, std::size_t operations_left) {
    const auto before = [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); };
    const std::size_t end = from + std::min(ranked_.size() - from, 2 * std::max<std::size_t>(operations_left, 1));
    const auto first = ranked_.begin() + std::ptrdiff_t(from), last = ranked_.begin() + std::ptrdiff_t(end);
    if (end < ranked_.size()) std::nth_element(first, last, ranked_.end(), before);
    std::sort(first, last, before);
    return end;
}

std::pair<double, double> AdaptiveFront::area_and_target(std::size_t j) const {
    const glm::dvec3 p(front_data_[j]);
    const double a = inkline::image_area(*camera_, front_data_[j].w, camera_->depth(p));
    const double t = criterion_->map ? criterion_->target_at(*camera_, p) : criterion_->target_area_px;
    return {a, t};
}

// Out of the band (as the scan tests it), free to change now and allowed by the tree order: a
// split, or a collapse whose children are all made. (A collapse waiting on its children is no
// lag: the scan finds it every frame, but it goes only after them.)
bool AdaptiveFront::ready_to_change(std::uint32_t v) const {
    const Vertex& x = rec(v);
    if (x.locked || x.retry_at > frame_) return false;
    const auto [a, t] = area_and_target(vertex_slot_[v]);
    if (a > criterion_->split * t) return x.last_collapse != none;
    return a < criterion_->collapse * t && x.collapse_of != none && x.pending_children == 0;
}

// The ranked candidates in their order, then the worklist (the vertices whose rings changed and
// that were not ranked: a ranked one is marked queued by the scan), until the budget runs out.
void AdaptiveFront::drain(std::size_t max_operations) {
    // (each collapse record changes at most once a frame, so a frame ends; the cap is a backstop)
    max_operations = std::min(max_operations, 2 * changed_in_frame_.size() + 16);
    std::size_t operations = 0, next = 0, sorted = 0, at = 0;
    while (operations < max_operations) {
        std::uint32_t v;
        if (next < ranked_.size()) {
            if (next == sorted) sorted = rank_next(next, max_operations - operations);
            v = ranked_[next++].second;
        } else if (at < work_.size()) {
            v = work_[at++];
        } else {
            break;
        }
        if (!dequeue(v)) continue;
        ++stats_->tried;
        if (try_split(v) || try_collapse(v)) ++operations;
    }
    // The budget ran out: the rest waits for the next frames. The ranked candidates not reached
    // were ready to change when the scan ranked them (it stamped those waiting on their children),
    // so they are the backlog as the scan found them; the worklist's rest is tested again.
    stats_->ranked = ranked_.size();
    stats_->deferred = stats_->backlog = ranked_.size() - next;
    for (; at < work_.size(); ++at)
        if (dequeue(work_[at])) {
            ++stats_->deferred;
            stats_->backlog += ready_to_change(work_[at]);
        }
    work_.clear();
    ranked_.clear();
}

FrontStats AdaptiveFront::update(const Camera& camera, const DetailCriterion& criterion, double frame_seconds,
                                 const FrontBudget& frame_budget) {
    const std::size_t max_operations = frame_budget.for_backlog(backlog_);
    const auto t0 = std::chrono::steady_clock::now();
    FrontStats s;
    camera_ = &camera;
    criterion_ = &criterion;
    stats_ = &s;
    if (std::uint16_t(++frame_) == 0) ++frame_;  // (frame16() 0 is every untouched record's)
    if (geomorphs_.enabled) advance_morphs(frame_seconds);
    s.layout_operations = lay_out_pools();
    const bool constant_target = !criterion.map;
    const bool budgeted = max_operations != SIZE_MAX;
    if (budgeted) {  // (the vertices the morphs' ends queued: the scan finds those out of the band, to rank them)
        for (const std::uint32_t v : work_) dequeue(v);
        work_.clear();
    }
    // image_area's terms hoisted out of the loop (the same operations, so the same bits): the scan
    // reads every active vertex a frame.
    const double focal2 = camera.focal() * camera.focal();
    const bool ortho = camera.is_ortho();
    const double nearest = camera.near_distance() > 0.0 ? camera.near_distance() : 1e-12;
    const std::size_t pool = vert_.size();
    const glm::vec4* data = front_data_.data();
    for (std::size_t j = 0; j < pool; ++j) {  // (the pool's order; a hole's NaN area passes no test)
        const glm::dvec3 p(data[j]);
        const double area = data[j].w;
        double a;
        if (ortho) {
            a = focal2 * area;
        } else {
            const double d = std::max(camera.depth(p), nearest);
            a = focal2 * area / (d * d);
        }
        const double t = constant_target ? criterion.target_area_px : criterion.target_at(camera, p);
        // (ready_to_change repeats this test through area_and_target: keep the two the same)
        if (!(a > criterion.split * t || a < criterion.collapse * t)) continue;
        Vertex& v = vert_[j];  // out of the band: can it change? (the rest is cold memory)
        if (v.locked || v.retry_at > frame_) continue;
        const bool split = a > criterion.split * t && v.last_collapse != none;
        if (!split && !(a < criterion.collapse * t && v.collapse_of != none)) continue;
        if (!budgeted) {
            found_.push_back({v.front_at, v.id});
            continue;
        }
        // A collapse waiting on its children (Hoppe's tree order) is refused and stamped here as
        // try_collapse would (a child's collapse clears the stamp), not ranked and left waiting
        // every frame.
        if (!split && v.pending_children != 0) {
            v.retry_at = frame_ + retry_frames;
            continue;
        }
        v.queued = frame16();  // (in the ranking: a change of its ring need not queue it again)
        ranked_.push_back({float(split ? a / (criterion.split * t) : criterion.collapse * t / a), v.id});
    }
    if (!budgeted) {  // (queued in the front's order: the pool's order must not change the operations)
        std::sort(found_.begin(), found_.end());
        for (const auto& [at, v] : found_) enqueue(v);
        found_.clear();
    }
    s.evaluated = front_id_.size();
    // (morphs that ended this frame made their collapses, and a pool laid out again took its time:
    // they count against the budget)
    const std::size_t spent = s.morphs_ended + s.layout_operations;
    const std::size_t budget = budgeted ? max_operations - std::min(max_operations, spent) : max_operations;
    drain(budget);
    s.budget = max_operations;
    backlog_ = s.backlog;
    trim_storage();
    s.morphs_running = morphs_.size();
    s.vertices = front_id_.size();
    s.triangles = active_face_count_;
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    camera_ = nullptr;
    criterion_ = nullptr;
    stats_ = nullptr;
    return s;
}

TriangleMesh AdaptiveFront::mesh(std::vector<std::uint32_t>* input_vertex, std::vector<std::uint32_t>* input_face) const {
    const PmInput in = pm_.input();
    TriangleMesh out;
    if (input_vertex) input_vertex->clear();
    if (input_face) input_face->clear();
    std::vector<std::uint32_t> index(in.positions.size(), none);
    for (std::uint32_t v = 0; v < in.positions.size(); ++v)
        if (active(v) && rec(v).head != none) {
            index[v] = std::uint32_t(out.positions.size());
            out.positions.push_back(in.positions[v]);
            if (input_vertex) input_vertex->push_back(v);
        }
    for (const Morph& m : morphs_) out.positions[index[m.vertex]] = shown(m);
    out.triangles.reserve(active_face_count_);
    for (std::uint32_t f = 0; f < in.triangles.size(); ++f) {
        const std::uint32_t slot = face_slot_[f];
        if (slot == none) continue;
        std::array<std::uint32_t, 3> t{index[face_vertex(slot, 0)], index[face_vertex(slot, 1)], index[face_vertex(slot, 2)]};
        // (keep the input's first corner first when it survives: an untouched face is the input's)
        const auto first = std::find(t.begin(), t.end(), index[in.triangles[f][0]]);
        if (first != t.end()) std::rotate(t.begin(), first, t.end());
        out.triangles.push_back(t);
        if (input_face) input_face->push_back(f);
        if (!in.face_object.empty()) out.face_object.push_back(in.face_object[f]);
    }
    if (!in.face_object.empty()) out.object_names = in.object_names;
    return out;
}

std::size_t AdaptiveFront::bytes() const {
    const auto b = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
    return b(vert_) + b(front_data_) + b(ring_) + b(front_id_) + b(vertex_slot_) + b(made_) + b(changed_in_frame_) + b(faces_) +
           b(face_id_) + b(face_slot_) + b(vert_holes_.bits) + b(face_holes_.bits) + b(work_) + b(found_) + b(morphs_) +
           b(ring_r_) + b(ring_k_) + b(touched_) + b(r_faces_) + b(r_areas_) + b(ranked_);
}

}  // namespace inkline
