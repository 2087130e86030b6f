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
#include "model/topology.hpp"

namespace inkline {

// The float filter of one view, for searches that keep their own per-face state: kFront/kBack
// where the float sign of the eye's distance to the face's plane is trusted, kUnknown where the
// exact predicate (face_is_front) must decide. FaceFacing runs the same filter.
struct FacingFilter {
    float ex = 0, ey = 0, ez = 0, w = 0, bound = 0;
    void bind(const MeshTopology& mesh, const Camera& camera);
    float signed_distance(const MeshTopology::FacingPlane& p) const {
        return p.nx * ex + p.ny * ey + p.nz * ez - w * p.d;
    }
    std::uint8_t operator()(const MeshTopology::FacingPlane& p) const {  // kBack 0, kUnknown 1, kFront 2
        const float det = signed_distance(p);
        return std::uint8_t(std::uint8_t(det > bound) + std::uint8_t(!(det < -bound)));
    }
};

// Appends the faces whose float distance to the eye (FacingFilter::signed_distance) is not above
// `limit`, in order; faces with an untrusted (NaN) plane are always included.
void faces_within(const MeshTopology& mesh, const FacingFilter& filter, float limit, std::vector<std::uint32_t>& out);

// For faces ids[0..n) with copies of their planes: sets each face's bit in front_bits where
// `now` says front and clears it elsewhere; appends to `check` the positions i where the two
// filters disagree or `now` cannot decide (the caller decides those exactly; where both filters
// agree and decide, the face kept its facing).
void band_states(const MeshTopology::FacingPlane* planes, const std::uint32_t* ids, std::size_t n,
                 const FacingFilter& now, const FacingFilter& before, std::uint64_t* front_bits,
                 std::vector<std::uint32_t>& check);

// Whether this CPU runs the AVX2 + BMI2 kernels (checked once; otherwise the scalar loops run).
bool cpu_has_avx2();

class FaceFacing {
public:
    static constexpr std::uint8_t kBack = 0, kUnknown = 1, kFront = 2;

    // Starts a view. Lazy: faces are decided on first use. The storage of the previous view is
    // reused and only the faces it touched are reset, so a view costs what it reads, not the mesh
    // size (the first view, or the first after a full scan, clears everything once).
    void begin_lazy(const MeshTopology& mesh, const Camera& camera);
    // Starts a view and decides every face (float filter for all, exact for the undecided ones
    // when they are first read); the filter pass split over `threads` threads.
    void begin_full(const MeshTopology& mesh, const Camera& camera, int threads = 1);

    // 1 if the eye is strictly on the front side of face f, else 0 (also for degenerate faces and
    // faces whose plane contains the eye). Not thread-safe: it caches what it computes.
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
    // followed by 3 readable bytes (so a 4-byte gather at any index <= face_count() stays inside).
    static constexpr std::uint8_t kSentinel = 3;
    static constexpr std::size_t kPad = 4;
    const std::uint8_t* states() const { return state_.data(); }
    std::size_t exact_tests() const { return exact_; }
    // Every face decided, as 0/1 (for tests and tools; O(faces)).
    std::vector<std::uint8_t> all() const;

private:
    void bind(const MeshTopology& mesh, const Camera& camera);
    std::uint8_t resolve(std::uint32_t f) const;
    std::uint8_t filter(std::uint32_t f) const;

    const MeshTopology* mesh_ = nullptr;
    Camera camera_;
    FacingFilter filter_;
    bool full_ = false;
    mutable std::vector<std::uint8_t> state_;
    mutable std::vector<std::uint32_t> touched_;  // lazy views: faces decided so far
    mutable std::size_t exact_ = 0;
};

}  // namespace inkline
