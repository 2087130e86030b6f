// The progressive mesh's active front, kept between frames (Hoppe 97's selective refinement on the
// half-edge hierarchy of progressive_mesh.hpp), with the real-time geomorphs of seed 000's
// section 3.2.
//
// Takes: a ProgressiveMesh (its input and collapse sequence), then per frame a Camera, the
// criterion and the frame's duration. Gives: the adapted mesh (its triangles, and per vertex the
// shown position: a vertex in a geomorph sits between its own position and its parent's).
//
// Each frame evaluates every active vertex (its ring's world area is cached, kept as an exact
// integer sum that the faces an operation changes update, so the test is one depth and one
// multiply) and splits or collapses only where the criterion says so; the work follows the
// vertices leaving [t_c T, t_s T], not the model's size. Records are kept for the
// active front only (the paper's point: one adaptive mesh is kept): per input vertex and face a
// 4-byte slot into pools of 32-byte vertex and face records that grow and shrink with the front
// (per face: its corners' current vertices, their links in the vertices' corner lists and its
// area; a restored face's corners come from the input's triangles). Per collapse: the faces it
// removed and the stacks of collapses made onto its vertices, so a split undoes the latest in
// O(degree x the hierarchy's depth there). No allocation per frame once the worklists and pools
// have grown; a pool left mostly empty by a coarsening is compacted at a frame's start, on its budget.
//
// A collapse is made (the rules of ProgressiveMesh::adapt, plus Hoppe's tree order: r goes only
// with its whole subtree) when its removed vertex r is below t_c T, its kept vertex k is active
// and a neighbour, the link condition holds, no face turns over and no vertex of the changed
// rings ends above t_s T unless it was there and does not grow. That guard stops split/collapse
// cycles: a split is triggered only above t_s T, and no collapse makes a vertex cross t_s T. A
// vertex k is split (the latest collapse made onto it undone) when above t_s T, unless a removed
// face's third corner is no longer k's neighbour (Hoppe's vsplit legality, in the form this
// hierarchy needs), a changed ring would not be a disk, or a child would fall below t_c T. Each
// collapse record changes at most once a frame, so a frame always ends. A collapse refused by the
// hierarchy's rules or by a geomorph's lock on its parent is stamped and not tried again until its
// ring changes or a geomorph next to it ends, so blocked work costs nothing a frame.
//
// The front started from the input and converged at a view need not equal
// ProgressiveMesh::adapt's mesh for that view, nor the front converged there from another view:
// the criterion is a band, so every mesh with its vertices inside it is a fixed point, and which
// one is reached depends on the order of the operations (and on the path taken to the view).
// What both guarantee is the band (tests/test_progressive_mesh_front.cpp checks it and bounds the
// difference in triangle count).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "detail/progressive_mesh.hpp"

namespace inkline {

// Real-time geomorphs (section 3.2). A collapse locks r, k and r's ring, moves r onto k over
// `seconds`, then collapses; a split is made at once with r starting at k and moving out. The
// speed is multiplied by the discrepancy between the vertex's image area and the band's edge it
// crossed (at least 1, at most `max_speedup`), so fast camera moves do not leave the mesh far
// behind.
struct GeomorphOptions {
    bool enabled = false;  // off: operations take effect at once (a single converged frame)
    double seconds = 0.5;
    double max_speedup = 8.0;
};

// A frame's operation budget (VDPM's regulation), the front's one knob: `base` operations a
// frame, raised by the backlog the last frame left (the vertices out of the band that could have
// changed and were deferred) over `catch_up_frames` frames, never above `most`. A fixed budget is
// base = most (`fixed(N)`: N a frame whatever the backlog); none is no budget (`none()`: every
// vertex that can change does, in scan order). The rule that follows the lag (`following_lag()`)
// takes a sustained demand above `base` as it comes, up to `most` (the bound on a frame's work),
// and makes up what a frame defers within a few frames once the demand falls, instead of lagging
// the view for the rest of the path as a fixed budget below the path's mean demand does.
// Operations counted: splits, collapses, geomorph starts and ends (an end makes its collapse:
// measured as costly as a start).
struct FrontBudget {
    std::size_t base = SIZE_MAX;      // SIZE_MAX: no budget
    std::size_t catch_up_frames = 1;  // (at least 1)
    std::size_t most = SIZE_MAX;
    static FrontBudget none() { return {}; }
    static FrontBudget fixed(std::size_t operations) { return {operations, 1, operations}; }
    // Chosen on the 1 M-triangle slow dolly with geomorphs (docs/progressive_mesh.md, "A budget
    // that follows the lag"): 800 operations are about 4.4 ms there by the measured cost of one
    // (starts and ends alike), and the lag is made up well before the path's end.
    static FrontBudget following_lag() { return {500, 4, 800}; }
    bool budgeted() const { return base != SIZE_MAX; }
    // The frame's budget after a frame that left `backlog` ready vertices deferred (SIZE_MAX: none).
    std::size_t for_backlog(std::size_t backlog) const {
        if (!budgeted()) return SIZE_MAX;
        return std::min(most, base + backlog / std::max<std::size_t>(1, catch_up_frames));
    }
    // At most `operations` a frame on top of this rule (a cap on base and most).
    FrontBudget capped(std::size_t operations) const {
        return {std::min(base, operations), catch_up_frames, std::min(most, operations)};
    }
};

// World areas as exact fixed-point integers: a face's area rounded to a whole number of `unit`s,
// a vertex's ring area a running sum of its faces' (what a change of a face adds and takes away).
// Integer sums are exact and order-free, so a sum kept over a session of operations is the one a
// fresh sum of the ring would give, bit for bit, whatever the history; a double running sum would
// drift by its roundings and make decisions depend on the path. The unit is the largest for which
// no ring can overflow: a face in the input's bounding box (diagonal D) has area at most D^2 / 2,
// a ring at most the input's F faces, so unit = F D^2 / 2^63 keeps every sum below 2^62. A face's
// rounding, half a unit, is 2^-24 of the mean face on the 1 M-triangle models (armadillo@2,
// bunny00@2; 2^-32 at 52 k): about the float ring mean's own rounding.
struct AreaUnits {
    double unit = 1.0, per_unit = 1.0;
    static AreaUnits for_input(const PmInput& input);
    std::int64_t of(double world_area) const { return std::int64_t(world_area * per_unit + 0.5); }
    // A ring's mean area in the world (what the criterion reads) from its sum and face count.
    float mean(std::int64_t sum, std::uint32_t faces) const {
        return faces ? float(double(sum) * unit / double(faces)) : 0.0f;
    }
};

struct FrontStats {
    std::size_t splits = 0, collapses = 0;  // logical operations made this frame
    std::size_t morphs_started = 0, morphs_running = 0;
    std::size_t evaluated = 0;               // vertices tested against the criterion
    std::size_t tried = 0;                   // vertices taken off the worklist and tried
    std::size_t morphs_ended = 0;            // geomorphs finished this frame (a collapse's made then)
    // A budgeted frame's candidates from the scan: out of the band and ready to change (a split,
    // or a collapse whose children are all made: Hoppe's tree order; the scan stamps the others).
    std::size_t ranked = 0;
    std::size_t deferred = 0;                // left untried for the next frames by the budget
    // Of the deferred, those ready to change (the ranked ones as the scan found them, the vertices
    // queued by this frame's changes tested again), the lag a FrontBudget follows; and this
    // frame's budget (SIZE_MAX: none).
    std::size_t backlog = 0, budget = SIZE_MAX;
    // A pool laid out again this frame: its cost in operations, taken from a budgeted frame's
    // budget (the records moved, about 256 to an operation's time).
    std::size_t layout_operations = 0;
    std::size_t vertices = 0, triangles = 0; // of the active front after the frame
    double largest_move_px = 0.0;            // largest shown-vertex move by a geomorph this frame
    double seconds = 0.0;
};

class AdaptiveFront {
public:
    // The front starts as the input (every vertex active). `pm` must outlive the front.
    explicit AdaptiveFront(const ProgressiveMesh& pm, GeomorphOptions geomorphs = {});

    // One frame: evaluates the active vertices at `camera` and splits/collapses until no vertex
    // that can change is out of the band; with geomorphs, running morphs advance by
    // `frame_seconds` first and collapses only start. `budget` gives the frame's operations from
    // the last frame's backlog (VDPM's regulation, so the work a frame is bounded when many
    // vertices leave the band at once): geomorphs ending and operations made count against it,
    // the vertices are taken largest discrepancy from the band first, and the rest wait for the
    // next frames' scans. With none they are taken in scan order.
    FrontStats update(const Camera& camera, const DetailCriterion& criterion, double frame_seconds = 0.0,
                      const FrontBudget& budget = FrontBudget::none());
    std::size_t backlog() const { return backlog_; }  // the last frame's (FrontStats::backlog)

    // The active front as a mesh: vertices in input order at their shown positions, faces in
    // input order with the input's first corner first when it survives (as ProgressiveMesh::adapt).
    // `input_vertex`, `input_face`: each vertex's and face's index in the input, when asked.
    TriangleMesh mesh(std::vector<std::uint32_t>* input_vertex = nullptr,
                      std::vector<std::uint32_t>* input_face = nullptr) const;

    std::size_t active_vertices() const { return front_id_.size(); }
    std::size_t active_faces() const { return active_face_count_; }
    // In the front (input vertex v; a vertex in no face never is).
    bool is_active(std::uint32_t v) const { return active(v); }
    bool is_locked(std::uint32_t v) const { return active(v) && rec(v).locked != 0; }  // held by a geomorph
    // The hierarchy's limits at a vertex: no collapse was made onto it (the bottom: it cannot
    // split), it is never removed (the top: it cannot collapse).
    bool at_bottom(std::uint32_t v) const;
    bool at_top(std::uint32_t v) const { return collapse_of(v) == none; }
    std::size_t morphs_running() const { return morphs_.size(); }
    // The criterion's A_img of an active vertex (its logical ring at its input position).
    double image_area_of(std::uint32_t v, const Camera& camera) const;
    // Its ring's mean world area as the criterion reads it (AreaUnits::mean of the kept sum; 0 for a
    // vertex not in the front), and the units the sums are kept in.
    float ring_area_of(std::uint32_t v) const { return ring_area(v); }
    const AreaUnits& area_units() const { return units_; }
    // The active vertices whose kept ring sum or face count differs from a fresh sum of their ring's
    // faces, each face's area measured again from its corners (a check: always 0).
    std::size_t ring_sums_differing() const;
    // Bytes of the front's arrays (the hierarchy and the input apart).
    std::size_t bytes() const;
    // Where an active vertex's record and an active input face's record sit in their pools (the
    // slot, in records): ring neighbours' records near each other share cache lines and pages.
    std::uint32_t vertex_record(std::uint32_t v) const { return vertex_slot_[v]; }
    std::uint32_t face_record(std::uint32_t input_face) const { return face_slot_[input_face]; }

private:
    static constexpr std::uint32_t none = UINT32_MAX;
    // What a frame reads of a running morph is in its record (the morphs are streamed, where the
    // input's positions and r's area sit far apart: a few cache misses a morph a frame).
    struct Morph {
        std::uint32_t vertex;  // r: moving onto its parent (collapse) or out of it (split)
        std::uint32_t parent;  // k (read each frame: kept here, not looked up through the hierarchy)
        bool collapse;
        // r's ring area (a collapse's: its ring is locked, so it holds until the collapse is made)
        float ring_area;
        double progress, speed;  // progress in [0, 1]; speed in transitions per second
        glm::dvec3 from, to;     // the input positions it moves between (r to k, or k to r)
    };

    const ProgressiveMesh& pm_;
    GeomorphOptions geomorphs_;
    // A slot word with this bit set holds no record's index (below); index_mask keeps the rest.
    static constexpr std::uint32_t tag = 0x80000000u, index_mask = 0x7fffffffu;
    // Per active vertex, in one 32-byte record: an operation reads a vertex's fields together, so
    // one cache line a vertex instead of one a field. The records sit in a pool in the input's
    // (spatially coherent) order: a removal leaves a hole, a split's vertex takes a hole near its
    // parent's record; the pool is compacted in its order once a fifth is holes, and laid out in
    // the input's order again once an eighth of its records went to its end for want of a hole
    // near (a refining front). So a ring's records stay near each other, where moving the last
    // record into each gap scattered them over the pool within a few thousand operations.
    struct alignas(32) Vertex {
        std::uint32_t id;                // its input index
        std::uint32_t head;              // first corner of its corner list
        std::uint32_t collapse_of;       // the collapse that removes it (none: a root)
        std::uint32_t last_collapse;     // latest collapse made onto it (a stack through made_[i].prev)
        std::uint32_t pending_children;  // collapses onto it not made yet
        // The frame from which the scan tests it again after a refusal that only a change nearby
        // can lift, so blocked vertices cost nothing a frame: a change of its ring or the end of a
        // morph next to it clears the stamp; the stamp's length is only a backstop.
        std::uint32_t retry_at;
        std::uint32_t front_at;          // its place in front_id_
        std::uint16_t locked : 15;       // geomorphs holding it
        // A neighbour's collapse onto it was refused for its lock or its ring (the link condition)
        // and stamped: the end of its lock or a change of its ring wakes its stamped neighbours.
        std::uint16_t waited_on : 1;
        // The frame it was queued in (frame16(); 0: not queued), so that a budgeted frame's
        // candidates left untried need no pass to unmark them.
        std::uint16_t queued;
    };
    static_assert(sizeof(Vertex) == 32);
    std::vector<Vertex> vert_;
    // The front's order (input vertices; a removal moves the last into the gap): the unbudgeted
    // frame queues the scan's vertices in this order, as when it was the records' own order, so
    // its operations do not depend on where the records sit.
    std::vector<std::uint32_t> front_id_;
    // A pool's holes, a bit a slot (set: free), how many, and the records placed at the pool's end
    // since it was laid out in the input's order (no hole was near their neighbours').
    struct Holes {
        std::vector<std::uint64_t> bits;
        std::size_t count = 0, misplaced = 0;
        void grow(std::size_t slots) { bits.resize((slots + 63) / 64, 0); }
        void free(std::uint32_t s) { bits[s / 64] |= std::uint64_t(1) << (s % 64); ++count; }
        void take(std::uint32_t s) { bits[s / 64] &= ~(std::uint64_t(1) << (s % 64)); --count; }
        bool is_free(std::uint32_t s) const { return bits[s / 64] >> (s % 64) & 1; }
        std::uint32_t near(std::uint32_t slot) const;  // a hole within a few KiB of `slot` (none: none)
    };
    Holes vert_holes_, face_holes_;
    static constexpr std::size_t gap_every = 8;  // a pool laid out again keeps a hole after every 8 records
    // Per input vertex: its record's index when active, else tag | the collapse that removed it
    // (tag | index_mask: a vertex in no face, never in the front). An inactive vertex needs nothing
    // more: all collapses onto it were made (tree order), it is unlocked and unqueued, and its
    // stack waits in made_.
    std::vector<std::uint32_t> vertex_slot_;
    static constexpr std::uint32_t retry_frames = 8;           // refused by the collapse's rules
    static constexpr std::uint32_t lock_backstop_frames = 64;  // waiting on a morph's lock
    // Per collapse, meaningful while it is made: the link of its kept vertex's stack, its removed
    // vertex's own stack (given back by the split) and the faces it removed (input indices). One
    // record: the collapse and its split read them together.
    struct Made {
        std::uint32_t prev;
        std::uint32_t removed_stack;
        std::array<std::uint32_t, 2> dead;
    };
    std::vector<Made> made_;
    // The frame it was last made or undone in, modulo 2^16 (a record last changed 2^16 frames ago
    // waits one frame: harmless, and half the bytes).
    std::vector<std::uint16_t> changed_in_frame_;
    std::uint32_t frame_ = 0;
    // Per active face (a pool slot s, its corner j is 4 s + j): its corners' current vertices
    // (input indices), each corner's link in its vertex's corner list and the face's world area,
    // updated where a corner changes, so that a ring's area is a sum of stored values. One 32-byte
    // record, so a ring walk reads one cache line a face. The lists are singly linked: a vertex's
    // list is as short as its degree, so unlinking by a walk costs less than a back link's 4 bytes
    // a corner.
    struct alignas(32) Face {
        std::uint32_t vertex[3];
        std::uint32_t next[3];
        std::int64_t area;  // in units_ (AreaUnits: exact sums)
    };
    std::vector<Face> faces_;
    // per slot: its input face (a hole: none). A face's slot is a hole near the slot of a face
    // next to it (as the vertices' records: ring neighbours share cache lines).
    std::vector<std::uint32_t> face_id_;
    std::vector<std::uint32_t> face_slot_;  // per input face: its slot (none: not in the front)
    std::size_t active_face_count_ = 0;
    std::vector<std::uint32_t> work_;  // input vertices
    std::size_t backlog_ = 0;          // the last frame's FrontStats::backlog
    // A budgeted frame's candidates from the scan with their discrepancy from the band (the
    // factor by which the vertex's image area lies outside it), ranked and taken before the worklist.
    std::vector<std::pair<float, std::uint32_t>> ranked_;
    // Per vertex record, beside vert_: the vertex's position and ring area (NaN in a hole, so the
    // scan passes over it), so that a frame's evaluation streams through memory instead of missing
    // the cache twice a vertex.
    std::vector<glm::vec4> front_data_;
    // Per vertex record, beside vert_: its ring's area sum (units_) and face count, kept by the
    // faces that change (linked, unlinked, their area changed), so an operation updates the rings
    // it changes instead of summing them again; front_data_'s area is AreaUnits::mean of it.
    struct RingSum {
        std::int64_t sum;
        std::uint32_t faces, unused;
    };
    std::vector<RingSum> ring_;
    AreaUnits units_;
    // The unbudgeted scan's vertices with their place in the front, to queue them in its order.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> found_;
    std::vector<Morph> morphs_;
    // Scratch (kept to avoid allocation per operation).
    std::vector<std::uint32_t> ring_r_, ring_k_, touched_;
    std::vector<std::uint32_t> r_faces_;  // a collapse's r: its ring's faces (pool slots)
    std::vector<std::int64_t> r_areas_;   // and their areas after it (units_; -1: removed)
    // This frame's view.
    const Camera* camera_ = nullptr;
    const DetailCriterion* criterion_ = nullptr;
    FrontStats* stats_ = nullptr;

    static std::uint32_t face_of(std::uint32_t corner) { return corner >> 2; }  // a pool slot
    static std::uint32_t slot_of(std::uint32_t corner) { return corner & 3; }   // the corner's place in it
    std::uint32_t face_vertex(std::uint32_t face, int j) const { return faces_[face].vertex[j]; }
    bool active(std::uint32_t v) const { return !(vertex_slot_[v] & tag); }
    Vertex& rec(std::uint32_t v) { return vert_[vertex_slot_[v]]; }  // (active v; moves with the front)
    const Vertex& rec(std::uint32_t v) const { return vert_[vertex_slot_[v]]; }
    std::uint32_t collapse_of(std::uint32_t v) const;
    std::uint32_t& corner_vertex(std::uint32_t c) { return faces_[face_of(c)].vertex[slot_of(c)]; }
    std::uint32_t& next_corner(std::uint32_t c) { return faces_[face_of(c)].next[slot_of(c)]; }
    std::uint32_t next_corner(std::uint32_t c) const { return faces_[face_of(c)].next[slot_of(c)]; }
    std::uint32_t parent(std::uint32_t v) const;
    std::uint16_t frame16() const { return std::uint16_t(frame_); }
    // A vertex in a morph is shown between its position and its parent's; the parent stays put (it
    // is locked, so it is in no morph of its own).
    static glm::dvec3 shown(const Morph& m) { return glm::mix(m.from, m.to, m.progress); }
    std::uint32_t representative(std::uint32_t input_vertex) const;
    void link(std::uint32_t c, std::uint32_t v);
    void unlink(std::uint32_t c);
    // A slot holding its input corners' representatives, a hole near `near_slot` when there is one.
    std::uint32_t add_face(std::uint32_t input_face, std::uint32_t near_slot = none);
    void remove_face(std::uint32_t slot);
    void relay_faces(bool input_order);
    void relay_vertices(bool input_order);
    // Lays the pools out again when due (holes, records out of place) and returns its cost in
    // operations, which a budgeted frame's budget pays; trim_storage gives back what the front
    // no longer needs.
    std::size_t lay_out_pools();
    void trim_storage();
    void front_add(std::uint32_t v, std::uint32_t collapse_of, std::uint32_t last_collapse, std::uint32_t pending,
                   std::uint32_t near_slot = none);
    void front_remove(std::uint32_t v, std::uint32_t removed_by);
    std::int64_t face_area(std::uint32_t f) const;  // measured from its corners' positions
    void refresh_face_area(std::uint32_t f);        // measured again, its corners' sums kept
    void refresh_ring_area(std::uint32_t v);        // front_data_'s area from the kept sum
    void neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) const;  // in ring order
    std::size_t sorted_ring(std::uint32_t v, std::vector<std::uint32_t>& out) const;
    double scale(std::uint32_t v) const;
    double target(std::uint32_t v) const;
    // The average world area of an active vertex's ring, kept in front_data_ only (0 for a vertex
    // in no face).
    float ring_area(std::uint32_t v) const { return active(v) ? front_data_[vertex_slot_[v]].w : 0.0f; }
    double image_area(std::uint32_t v) const { return scale(v) * ring_area(v); }
    void enqueue(std::uint32_t v);
    bool dequeue(std::uint32_t v);  // clears v's mark; whether v (active, in a face) can change
    void enqueue_changed(std::uint32_t v);
    void wake_around(std::uint32_t v);
    void unlock(std::uint32_t v);
    bool refuse(std::uint32_t v, std::uint32_t frames);  // stamps v; returns false

    bool collapse_ok(std::uint32_t r, std::uint32_t k);
    bool flips_else_list_faces(std::uint32_t r, std::uint32_t k);
    float ring_area_after_collapse(std::uint32_t u, std::uint32_t k) const;
    void raw_collapse(std::uint32_t r);
    bool split_ok(std::uint32_t k) const;
    bool ring_is_disk(std::uint32_t v) const;
    std::uint32_t raw_split(std::uint32_t k);  // returns the vertex split off
    void touch_ring(std::uint32_t v);          // refresh areas of v and its neighbours, queue them
    void collapse_made(std::uint32_t r);       // raw_collapse, then r's ring (ring_r_) refreshed and queued
    bool try_collapse(std::uint32_t r);
    bool try_split(std::uint32_t k);
    void lock_ring(std::uint32_t r, int delta);
    void advance_morphs(double frame_seconds);
    void drain(std::size_t max_operations);
    // The scan's test of front entry j: its image area, and T there.
    std::pair<double, double> area_and_target(std::size_t j) const;
    bool ready_to_change(std::uint32_t v) const;  // a deferred vertex counted in the backlog
    std::size_t rank_next(std::size_t from, std::size_t operations_left);
};

}  // namespace inkline
