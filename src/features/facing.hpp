// Facing of the mesh's faces for one view, exact, computed either for every face in one
// vectorizable pass (the exhaustive finder) or face by face on first use (the randomized finder,
// the visibility stage's walks). Takes MeshTopology + Camera; gives front/back per face.
//
// Each face is decided by a float filter on the topology's unit-normal planes; a face whose float
// signed distance to the eye is within the view's bound of zero (or whose plane is NaN) is decided
// by the exact orientation predicate instead (CGAL's filtered predicate; features.hpp
// face_is_front). So the answer is always that of the exact predicate.
#pragma once

#include <cstdint>
#include <vector>

#include "core/camera.hpp"
#include "core/worker_thread.hpp"
#include "model/topology.hpp"

namespace inkline {

struct FacingKernels;  // facing_kernels.hpp: the inner loops, one instruction set a file
// The kernels this CPU runs best (chosen once, on first use), or with false the portable ones:
// the same results either way.
const FacingKernels& facing_kernels(bool vector = true);

// The float filter of one view, for searches that keep their own per-face state: kFront/kBack
// where the float sign of the eye's distance to the face's plane is trusted, kUnknown where the
// exact predicate (face_is_front) must decide. FaceFacing runs the same filter.
struct FacingFilter {
    float ex = 0, ey = 0, ez = 0, w = 0, bound = 0;
    void bind(const MeshTopology& mesh, const Camera& camera);
    // The filter of an eye vector e (eye - facing_origin; an orthographic view: -forward, w = 0).
    void bind(const MeshTopology& mesh, const double e[3], double w);
    float signed_distance(const MeshTopology::FacingPlane& p) const {
        return p.nx * ex + p.ny * ey + p.nz * ez - w * p.d;
    }
    std::uint8_t operator()(const MeshTopology::FacingPlane& p) const {  // kBack 0, kUnknown 1, kFront 2
        const float det = signed_distance(p);
        return std::uint8_t(std::uint8_t(det > bound) + std::uint8_t(!(det < -bound)));
    }
};

// Blocks of kFaces consecutive faces (in the Hilbert order of the model: compact patches) with
// the range of their float planes, so that a view can decide a whole block at once where every
// face of it has the same filter state (the exact answer), and skip reading its planes and its
// edges. Built once per mesh, by the searches that use it (about 1 byte per face: 32 bytes of
// ranges, 4 of edge offset and the neighbour block list, per block of 64 faces). Ranges of the
// planes themselves, not of offsets from a centre per block: those skip too few more planes to
// pay for their bytes (bench/results/finder.md).
class FaceBlocks {
public:
    static constexpr std::uint32_t kFaces = 64;
    void build(const MeshTopology& mesh);  // the plane ranges
    // build() in steps: start() sizes the blocks for the mesh (ranges undefined), build_range()
    // computes the ranges of blocks [b0, b1) (FaceFacing::begin_full_building).
    void start(const MeshTopology& mesh);
    void build_range(std::size_t b0, std::size_t b1);
    void build_edges();                    // the edge ranges (after build; tried once; the exhaustive
                                           // finder builds them only where it does not use BlockEdges)
    bool edges_tried() const { return edges_tried_; }
    bool built_for(const MeshTopology& mesh) const { return mesh_ == &mesh && nf_ == mesh.face_count(); }
    std::size_t size() const { return bounds_.size(); }
    std::size_t bytes() const;
    // The range of the filter's float distance (FacingFilter::signed_distance) over the faces of
    // block b, widened by the float evaluation's error: every face's float distance lies in
    // [lo, hi]. NaN if the block holds an untrusted (NaN) plane.
    void distance_range(std::size_t b, const FacingFilter& f, double& lo, double& hi) const;
    // The same for a block's ranges given as lo[4], hi[4] (the kernels' layout).
    static void distance_range(const float* bounds, const FacingFilter& f, double& lo, double& hi);
    // kFront / kBack where the filter gives that state for every face of block b, else kUnknown.
    std::uint8_t classify(std::size_t b, const FacingFilter& f) const;
    // classify(b, f) for blocks [b0, b1) into out[b - b0] (the same operations, four blocks a step).
    void classify(std::size_t b0, std::size_t b1, const FacingFilter& f, std::uint8_t* out) const;
    // The same against +-limit instead of the filter's bound: kFront where every face's float
    // distance is above limit, kBack where every one is below -limit, else (or NaN) kUnknown.
    void classify_within(std::size_t b0, std::size_t b1, const FacingFilter& f, double limit, std::uint8_t* out) const;
    // Edges by block: [edge_begin(b), edge_begin(b + 1)) are the edges whose first face lies in
    // block b (edges are numbered in the order of their first face). has_edges() is false before
    // build_edges() or when the mesh numbers its edges otherwise (then no edge range is skipped).
    bool has_edges() const { return !edge_begin_.empty(); }
    std::uint32_t edge_begin(std::size_t b) const { return edge_begin_[b]; }
    // Whether the edges of block b can be skipped in a view whose block states are `cls`: block
    // b and every block holding a second face of its edges have the same uniform state (so none
    // of those edges has faces of different facing), and none of its edges is a border.
    bool edges_uniform(std::size_t b, const std::uint8_t* cls) const {
        const std::uint8_t s = cls[b];
        if (s == 1) return false;  // FaceFacing::kUnknown
        for (std::uint32_t k = nbr_begin_[b]; k < nbr_begin_[b + 1]; ++k)
            if (nbr_[k] == kBorderBlock || cls[nbr_[k]] != s) return false;
        return true;
    }

private:
    static constexpr std::uint32_t kBorderBlock = UINT32_MAX;
    struct Bounds {
        float lo[4], hi[4];  // nx, ny, nz, d (NaN: the block holds an untrusted plane)
    };
    const MeshTopology* mesh_ = nullptr;
    std::size_t nf_ = 0;
    bool edges_tried_ = false;
    std::vector<Bounds> bounds_;
    std::vector<std::uint32_t> edge_begin_, nbr_begin_, nbr_;
};

// The edges of each block of FaceBlocks::kFaces faces, laid out for a scan of a full view's
// states without gathers (the exhaustive finder's edge scan). Each edge is checked from the
// corner that numbers it (edges are numbered in the order of their first corner: topology.cpp),
// so the candidates come out in edge order. Per block (base = its first face): a byte per
// corner (corner-major, 192 bytes) indexes the state of the corner's neighbour face in two
// windows of 128 faces, [base, base + 128) (0..127) and [base2, base2 + 128) (128..255, base2
// chosen per block to hold most of the other neighbours); a corner that does not number its
// edge, or whose edge is a border, indexes its own face (never a candidate). The neighbours in
// neither window (a few percent of the edges: bench/results/finder.md) are listed as escapes (face,
// neighbour, corner). A bit per corner says which corners number an edge, so a candidate's
// edge id is the block's first edge plus the owned corners before it. About 3.5 bytes per face
// (192 + 24 + 12 bytes per block of 64 faces, 9 bytes per escape).
class BlockEdges {
public:
    static constexpr std::uint32_t kFaces = FaceBlocks::kFaces;
    static constexpr std::uint32_t kCheck = 0x80000000u;  // candidate flag: a face is undecided
    // False (and empty) where the mesh numbers its edges otherwise or has 2^31 edges or more.
    bool build(const MeshTopology& mesh);
    bool built_for(const MeshTopology& mesh) const { return mesh_ == &mesh && nf_ == mesh.face_count() && !base2_.empty(); }
    std::size_t size() const { return base2_.size(); }  // blocks
    std::size_t escapes() const { return esc_self_.size(); }
    std::uint32_t edge_begin(std::size_t b) const { return edge_begin_[b]; }  // edges numbered in block b: [b, b + 1)
    std::size_t bytes() const;
    // Appends the candidate edges of blocks [b0, b1) in edge order: edges whose two faces are
    // decided and differ, and (flagged kCheck) edges with an undecided face, which the caller
    // decides exactly: the same edges as a scan of every edge for "states differ or the first
    // face is undecided", borders left out. `states` are FaceFacing::states() of a full view
    // (padded by FaceFacing::kPad). Blocks for which skip(b) holds are not read (the caller's
    // proof that none of their edges is a candidate), nor the index of blocks whose two windows
    // hold one decided state. `kernels`: facing_kernels() or a given table (the same result).
    // Returns the number of edges of the blocks whose index was read.
    template <class Skip>
    std::size_t scan(const std::uint8_t* states, std::uint32_t b0, std::uint32_t b1, Skip skip,
                     std::vector<std::uint32_t>& out, const FacingKernels& kernels) const {
        std::vector<std::uint16_t> esc;
        escape_bits(states, b0, b1, esc, kernels);
        std::size_t read = 0;
        for (std::uint32_t b = b0; b < b1; ++b)
            if (!skip(b) && scan_block(states, b, esc.data(), esc_begin_[b0], out, kernels))
                read += edge_begin_[b + 1] - edge_begin_[b];
        return read;
    }
    // `simd`: this CPU's kernels, or with false the portable ones.
    template <class Skip>
    std::size_t scan(const std::uint8_t* states, std::uint32_t b0, std::uint32_t b1, Skip skip,
                     std::vector<std::uint32_t>& out, bool simd = true) const {
        return scan(states, b0, b1, skip, out, facing_kernels(simd));
    }
    // Whether this CPU runs a vector kernel: AVX-512 VBMI (byte permutations over the windows),
    // else AVX2 + BMI2 (the windows as bit planes, looked up by in-lane shuffles).
    static bool has_simd();

private:
    // Candidate bits of the escapes of blocks [b0, b1) (16 a word, from the first escape of b0).
    void escape_bits(const std::uint8_t* states, std::uint32_t b0, std::uint32_t b1, std::vector<std::uint16_t>& bits,
                     const FacingKernels& kernels) const;
    bool scan_block(const std::uint8_t* states, std::uint32_t b, const std::uint16_t* esc, std::uint32_t esc0,
                    std::vector<std::uint32_t>& out, const FacingKernels& kernels) const;
    const MeshTopology* mesh_ = nullptr;
    std::size_t nf_ = 0;
    std::vector<std::uint8_t> index_;             // 192 per block: corner k of face j at k * 64 + j
    std::vector<std::uint64_t> owned_;            // 3 per block: bit 3 j + k, the corner numbers its edge
    std::vector<std::uint32_t> edge_begin_;       // first edge of each block (+ the end)
    std::vector<std::uint32_t> base2_;            // second window of each block
    std::vector<std::uint32_t> esc_begin_;        // escapes of each block (+ the end)
    std::vector<std::uint32_t> esc_self_, esc_far_;  // the corner's face and its neighbour
    std::vector<std::uint8_t> esc_corner_;        // k * 64 + j
};

// The faces of a coherence band (ascending ids) with copies of their planes as four float rows
// and the 64-face words of a per-face bit set they fall in (word, mask of the band's faces in it),
// so that a view streams the rows and, where it writes the band's bits, writes each word once.
// 20 bytes per band face plus 12 per word.
class FacingBand {
public:
    void assign(const MeshTopology& mesh, const std::vector<std::uint32_t>& faces);
    // The band of the faces whose float distance to the eye (FacingFilter::signed_distance) is
    // not above `limit`, in order; faces with an untrusted (NaN) plane are always included. The
    // planes are written to the rows as they are read. With blocks (built for this mesh), blocks
    // whose range is beyond the limit are not read. Returns the number of faces whose planes were
    // read. With `front` (face_count() / 64 + 1 words): sets the bit of every face outside the
    // band whose float distance is above zero (above the limit) and clears it for the others
    // outside (below -limit); bits of faces in the band are left arbitrary. With limit >= the
    // filter's bound, a bit outside the band is the exact facing. `simd` as for states().
    std::size_t select(const MeshTopology& mesh, const FacingFilter& filter, float limit, const FaceBlocks* blocks,
                       std::uint64_t* front, bool simd = true);
    std::size_t select(const MeshTopology& mesh, const FacingFilter& filter, float limit, const FaceBlocks* blocks,
                       std::uint64_t* front, const FacingKernels& kernels);
    std::size_t size() const { return n_; }
    std::uint32_t face(std::size_t i) const { return ids_[i]; }
    MeshTopology::FacingPlane plane(std::size_t i) const { return {nx_[i], ny_[i], nz_[i], d_[i]}; }
    // Appends to `check` the positions i where the two filters disagree or `now` cannot decide
    // (the caller decides those exactly; where both filters agree and decide, the face kept its
    // facing). With front_bits, also sets each band face's bit where `now` says front and clears
    // it elsewhere (other bits untouched); with nullptr no bit is written (a caller whose bits
    // hold the previous view's facing need only set those of the faces checked). `simd`: this
    // CPU's kernels (facing_kernels()), or with false the portable ones (the same result).
    void states(const FacingFilter& now, const FacingFilter& before, std::uint64_t* front_bits,
                std::vector<std::uint32_t>& check, bool simd = true);
    void states(const FacingFilter& now, const FacingFilter& before, std::uint64_t* front_bits,
                std::vector<std::uint32_t>& check, const FacingKernels& kernels);

private:
    void finish();  // the words and the scratch, for the n_ faces in the rows
    void room(std::size_t len);  // rows at least len long (kept between bands)
    // The rows hold n_ faces; they may be longer (select() keeps their length between bands, so
    // that a new band writes over the old without clearing it).
    std::size_t n_ = 0;
    std::vector<std::uint32_t> ids_;
    std::vector<float> nx_, ny_, nz_, d_;
    std::vector<std::uint32_t> words_;
    std::vector<std::uint64_t> masks_;
    std::vector<std::uint8_t> front_;  // scratch: front bit per band face, 8 per byte (padded)
    std::vector<std::uint32_t> check_scratch_;  // scratch: states()' positions (room for the band)
};

class FaceFacing {
public:
    static constexpr std::uint8_t kBack = 0, kUnknown = 1, kFront = 2;

    // Starts a view. Lazy: faces are decided on first use. The storage of the previous view is
    // reused and only the faces it touched are reset, so a view costs what it reads, not the mesh
    // size (the first view, or the first after a full scan, clears everything once).
    void begin_lazy(const MeshTopology& mesh, const Camera& camera);
    // Starts a view and decides every face (float filter for all, exact for the undecided ones
    // when they are first read); the filter pass split over `threads` threads.
    // With blocks (built for this mesh), a block the filter decides as a whole is set without
    // reading its planes (the same states); block_states() then gives each block's state.
    // `team`: kept threads for the parts (else threads made for this call).
    void begin_full(const MeshTopology& mesh, const Camera& camera, int threads = 1, const FaceBlocks* blocks = nullptr,
                    WorkerTeam* team = nullptr);
    const std::vector<std::uint8_t>& block_states() const { return block_state_; }
    // begin_full(mesh, camera, 1, &blocks) with `blocks` built for the mesh in the same pass (a
    // chunk of blocks' ranges, then its states, while its planes are in the cache: the planes are
    // read from memory once, not once to build the blocks and again to decide). The same states,
    // blocks and block states.
    void begin_full_building(const MeshTopology& mesh, const Camera& camera, FaceBlocks& blocks);
    // Moves a full view on to `camera` given every face whose facing differs between the two
    // cameras (turned[0..n), exact: a coherent finder's follow): their decided states flip, faces
    // not decided yet stay undecided (decided on first read, for `camera`), everything else is
    // kept. Requires full(); the view stays full, so its reads cost what a full pass's do, at the
    // price of the turned faces only. Block states are dropped (they were the old camera's).
    void carry(const Camera& camera, const std::uint32_t* turned, std::size_t n);
    bool full() const { return full_; }
    // Bumped by every begin_full, begin_lazy and carry: a caller that left this view full for a
    // camera knows, by the generation it saw, that nobody started another view since.
    std::uint64_t generation() const { return generation_; }
    std::size_t planes_read() const { return planes_read_; }

    // While several threads read this view (set before they start, cleared after they join):
    // a face not decided yet is decided on each read and not cached, so reads are thread-safe.
    void set_shared(bool shared) const { shared_ = shared; }
    // 1 if the eye is strictly on the front side of face f, else 0 (also for degenerate faces and
    // faces whose plane contains the eye). Not thread-safe (it caches what it computes) unless
    // set_shared(true).
    std::uint8_t operator[](std::uint32_t f) const {
        const std::uint8_t s = state_[f];
        return (s == kUnknown ? resolve(f) : s) >> 1;
    }
    // Float signed distance of the eye to the face's plane (unit normal), for searches that
    // want to move toward a silhouette; NaN for untrusted planes. Never used for decisions.
    float signed_distance(std::uint32_t f) const;

    std::size_t size() const { return state_.empty() ? 0 : state_.size() - kPad; }
    std::size_t faces_decided() const { return full_ ? size() : touched_.size(); }
    // Raw states (kBack, kUnknown, kFront) of a full view, for scans that resolve kUnknown
    // themselves; index face_count() holds kSentinel (so a border's kNoFace, clamped, differs),
    // and so do the kPad - 1 bytes after it (so a 4-byte gather at any index <= face_count(), or
    // a 128-byte window from any face, stays inside: BlockEdges).
    static constexpr std::uint8_t kSentinel = 3;
    static constexpr std::size_t kPad = 128;
    const std::uint8_t* states() const { return state_.data(); }
    std::size_t exact_tests() const { return exact_; }
    // Every face decided, as 0/1 (for tests and tools; O(faces)).
    std::vector<std::uint8_t> all() const;

private:
    void bind(const MeshTopology& mesh, const Camera& camera);
    void start_full(const MeshTopology& mesh, const Camera& camera);
    std::size_t decide(std::size_t lo, std::size_t hi, const FaceBlocks* blocks);
    std::uint8_t resolve(std::uint32_t f) const;
    std::uint8_t filter(std::uint32_t f) const;

    const MeshTopology* mesh_ = nullptr;
    Camera camera_;
    FacingFilter filter_;
    bool full_ = false;
    std::uint64_t generation_ = 0;
    mutable std::vector<std::uint8_t> state_;
    mutable std::vector<std::uint32_t> touched_;  // lazy views: faces decided so far
    std::vector<std::uint8_t> block_state_;       // full views with blocks: kBack, kUnknown, kFront
    std::size_t planes_read_ = 0;
    mutable std::size_t exact_ = 0;
    mutable bool shared_ = false;
};

}  // namespace inkline
