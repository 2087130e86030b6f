#include "features/facing.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <thread>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/predicates.hpp"

namespace inkline {

// The view's bound. With E = eye - origin, R = facing_radius, the trusted unit normal n' within
// 2^-21 of the exact unit normal n* per component, d' within 2^-20 R of dot(n*, a - origin):
//   |dot(n', float(E)) - dot(n*, E)| <= 2^-21 |E|_1 + (2^-24 + eps)|E|_1 <= 2^-20 |E|_1,
//   float evaluation (3 products, 3 sums) <= 5 * 2^-24 (|E|_1 + R) < 2^-21 (|E|_1 + R),
// so the float distance errs by less than 2^-19 (|E|_1 + R); the bound takes twice that, plus an
// absolute floor for the subnormal range. Orthographic: E = -forward and no offset term (w = 0).
// Outside the bound the float sign is the exact sign; inside, the exact predicate decides.
void FacingFilter::bind(const MeshTopology& mesh, const Camera& camera) {
    const bool ortho = camera.is_ortho();
    const glm::dvec3 e = ortho ? -camera.forward() : camera.eye() - mesh.facing_origin;
    ex = float(e.x);
    ey = float(e.y);
    ez = float(e.z);
    w = ortho ? 0.0f : 1.0f;
    const double l1 = std::abs(e.x) + std::abs(e.y) + std::abs(e.z);
    bound = float(0x1p-18 * (l1 + (ortho ? 0.0 : mesh.facing_radius)) + 1e-36);
    if (!std::isfinite(ex) || !std::isfinite(ey) || !std::isfinite(ez) || !std::isfinite(bound))
        bound = INFINITY;  // out of float range: every face goes to the exact test
}

void FaceFacing::bind(const MeshTopology& mesh, const Camera& camera) {
    mesh_ = &mesh;
    camera_ = camera;
    exact_ = 0;
    filter_.bind(mesh, camera);
}

void FaceFacing::begin_lazy(const MeshTopology& mesh, const Camera& camera) {
    const std::size_t nf = mesh.face_count();
    if (full_ || state_.size() != nf + kPad || mesh_ != &mesh) {
        state_.assign(nf + kPad, kUnknown);
        state_[nf] = kSentinel;
    } else {
        for (std::uint32_t f : touched_) state_[f] = kUnknown;
    }
    touched_.clear();
    full_ = false;
    bind(mesh, camera);
}

namespace {

// Front 2, back 0, undecided (or NaN plane) 1, for faces [0, nf).
void facing_states_scalar(const MeshTopology::FacingPlane* __restrict p, std::size_t nf, const FacingFilter& flt,
                          std::uint8_t* __restrict out) {
    const float ex = flt.ex, ey = flt.ey, ez = flt.ez, w = flt.w, b = flt.bound;
    for (std::size_t f = 0; f < nf; ++f) {
        const float det = p[f].nx * ex + p[f].ny * ey + p[f].nz * ez - w * p[f].d;
        out[f] = std::uint8_t(std::uint8_t(det > b) + std::uint8_t(!(det < -b)));
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
// Eight consecutive planes (nx, ny, nz, d) transposed to four rows of eight lanes.
#define INKLINE_AVX2 __attribute__((target("avx2,bmi2"), always_inline))
struct Planes8 {
    __m256 nx, ny, nz, d;
};
INKLINE_AVX2 inline void load_planes8(const float* q, Planes8& out) {
    // a = planes 0|4, b = 1|5, c = 2|6, d = 3|7 (one 128-bit plane per half).
    const __m256 a = _mm256_loadu2_m128(q + 16, q), b = _mm256_loadu2_m128(q + 20, q + 4);
    const __m256 c = _mm256_loadu2_m128(q + 24, q + 8), d = _mm256_loadu2_m128(q + 28, q + 12);
    const __m256 t0 = _mm256_unpacklo_ps(a, b), t1 = _mm256_unpackhi_ps(a, b);
    const __m256 t2 = _mm256_unpacklo_ps(c, d), t3 = _mm256_unpackhi_ps(c, d);
    out.nx = _mm256_shuffle_ps(t0, t2, 0x44);
    out.ny = _mm256_shuffle_ps(t0, t2, 0xEE);
    out.nz = _mm256_shuffle_ps(t1, t3, 0x44);
    out.d = _mm256_shuffle_ps(t1, t3, 0xEE);
}
// The filter's eye (ex, ey, ez, w) in all lanes.
struct Eye8 {
    __m256 ex, ey, ez, w;
};
INKLINE_AVX2 inline void load_eye8(const FacingFilter& f, Eye8& out) {
    out.ex = _mm256_set1_ps(f.ex);
    out.ey = _mm256_set1_ps(f.ey);
    out.ez = _mm256_set1_ps(f.ez);
    out.w = _mm256_set1_ps(f.w);
}
// The filter's distance of the eye to eight planes: the same products and sums in the same order
// as FacingFilter::signed_distance (no FMA), so the same floats.
INKLINE_AVX2 inline void eye_distance8(const Planes8& p, const Eye8& e, __m256& out) {
    out = _mm256_sub_ps(
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(p.nx, e.ex), _mm256_mul_ps(p.ny, e.ey)), _mm256_mul_ps(p.nz, e.ez)),
        _mm256_mul_ps(e.w, p.d));
}
#endif

#if defined(__x86_64__) && defined(__GNUC__)
// The same with AVX2, 8 faces a step: the 8 planes transposed to 4 rows of 8 lanes (the same
// products and sums in the same order as the scalar loop, no FMA, so the same floats), the two
// comparisons as bit masks, spread to one byte per face with pdep.
__attribute__((target("avx2,bmi2"))) void facing_states_avx2(const MeshTopology::FacingPlane* __restrict p,
                                                             std::size_t nf, const FacingFilter& flt,
                                                             std::uint8_t* __restrict out) {
    Eye8 eye;
    load_eye8(flt, eye);
    const __m256 b = _mm256_set1_ps(flt.bound), nb = _mm256_set1_ps(-flt.bound);
    constexpr std::uint64_t kLowBits = 0x0101010101010101ull;
    std::size_t f = 0;
    for (; f + 8 <= nf; f += 8) {
        Planes8 p8;
        load_planes8(&p[f].nx, p8);
        __m256 det;
        eye_distance8(p8, eye, det);
        const unsigned front = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(det, b, _CMP_GT_OQ)));
        const unsigned not_back = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(det, nb, _CMP_NLT_UQ)));
        const std::uint64_t bytes = _pdep_u64(front, kLowBits) + _pdep_u64(not_back, kLowBits);
        std::memcpy(out + f, &bytes, 8);
    }
    facing_states_scalar(p + f, nf - f, flt, out + f);
}
#endif

// Faces whose float distance to the eye is not above limit (NaN planes included), appended.
void faces_within_scalar(const MeshTopology::FacingPlane* p, std::uint32_t f0, std::uint32_t f1, const FacingFilter& flt,
                         float limit, std::vector<std::uint32_t>& out) {
    for (std::uint32_t f = f0; f < f1; ++f)
        if (!(std::abs(flt.signed_distance(p[f])) > limit)) out.push_back(f);
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2,bmi2"))) void faces_within_avx2(const MeshTopology::FacingPlane* p, std::uint32_t nf,
                                                            const FacingFilter& flt, float limit,
                                                            std::vector<std::uint32_t>& out) {
    Eye8 eye;
    load_eye8(flt, eye);
    const __m256 lim = _mm256_set1_ps(limit);
    const __m256 abs_mask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    std::uint32_t f = 0;
    for (; f + 8 <= nf; f += 8) {
        Planes8 p8;
        load_planes8(&p[f].nx, p8);
        __m256 det;
        eye_distance8(p8, eye, det);
        // not (|det| > limit): NaN included
        unsigned m = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(_mm256_and_ps(det, abs_mask), lim, _CMP_NGT_UQ)));
        while (m) {
            out.push_back(f + unsigned(__builtin_ctz(m)));
            m &= m - 1;
        }
    }
    faces_within_scalar(p, f, nf, flt, limit, out);
}
#endif

void band_states_scalar(const MeshTopology::FacingPlane* planes, const std::uint32_t* ids, std::size_t i0, std::size_t n,
                        const FacingFilter& now, const FacingFilter& before, std::uint64_t* front_bits,
                        std::vector<std::uint32_t>& check) {
    for (std::size_t i = i0; i < n; ++i) {
        const std::uint8_t a = now(planes[i]), b = before(planes[i]);
        const std::uint32_t f = ids[i];
        const std::uint64_t m = std::uint64_t(1) << (f & 63);
        std::uint64_t& w = front_bits[f >> 6];
        w = a == FaceFacing::kFront ? (w | m) : (w & ~m);
        if (a != b || a == FaceFacing::kUnknown) check.push_back(std::uint32_t(i));
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2,bmi2"))) void band_states_avx2(const MeshTopology::FacingPlane* planes,
                                                           const std::uint32_t* ids, std::size_t n,
                                                           const FacingFilter& now, const FacingFilter& before,
                                                           std::uint64_t* front_bits, std::vector<std::uint32_t>& check) {
    Eye8 eye_now, eye_before;
    load_eye8(now, eye_now);
    load_eye8(before, eye_before);
    const __m256 ab = _mm256_set1_ps(now.bound), anb = _mm256_set1_ps(-now.bound);
    const __m256 bb = _mm256_set1_ps(before.bound), bnb = _mm256_set1_ps(-before.bound);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        Planes8 p8;
        load_planes8(&planes[i].nx, p8);
        __m256 da, db;
        eye_distance8(p8, eye_now, da);
        eye_distance8(p8, eye_before, db);
        const unsigned fa = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(da, ab, _CMP_GT_OQ)));
        const unsigned ka = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(da, anb, _CMP_NLT_UQ)));  // not back
        const unsigned fb = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(db, bb, _CMP_GT_OQ)));
        const unsigned kb = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(db, bnb, _CMP_NLT_UQ)));
        // states differ, or "now" undecided (not back and not front)
        unsigned odd = (fa ^ fb) | (ka ^ kb) | (ka & ~fa);
        for (unsigned j = 0; j < 8; ++j) {
            const std::uint32_t f = ids[i + j];
            const std::uint64_t m = std::uint64_t(1) << (f & 63);
            std::uint64_t& w = front_bits[f >> 6];
            w = (fa >> j) & 1 ? (w | m) : (w & ~m);
        }
        while (odd) {
            check.push_back(std::uint32_t(i + unsigned(__builtin_ctz(odd))));
            odd &= odd - 1;
        }
    }
    band_states_scalar(planes, ids, i, n, now, before, front_bits, check);
}
#endif

}  // namespace

bool cpu_has_avx2() {
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi2");
    return has;
#else
    return false;
#endif
}

void faces_within(const MeshTopology& mesh, const FacingFilter& filter, float limit, std::vector<std::uint32_t>& out) {
    const std::uint32_t nf = std::uint32_t(mesh.face_count());
#if defined(__x86_64__) && defined(__GNUC__)
    if (cpu_has_avx2()) return faces_within_avx2(mesh.facing.data(), nf, filter, limit, out);
#endif
    faces_within_scalar(mesh.facing.data(), 0, nf, filter, limit, out);
}

void band_states(const MeshTopology::FacingPlane* planes, const std::uint32_t* ids, std::size_t n,
                 const FacingFilter& now, const FacingFilter& before, std::uint64_t* front_bits,
                 std::vector<std::uint32_t>& check) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (cpu_has_avx2()) return band_states_avx2(planes, ids, n, now, before, front_bits, check);
#endif
    band_states_scalar(planes, ids, 0, n, now, before, front_bits, check);
}

void FaceFacing::begin_full(const MeshTopology& mesh, const Camera& camera, int threads) {
    bind(mesh, camera);
    const std::size_t nf = mesh.face_count();
    state_.resize(nf + kPad);
    std::fill(state_.begin() + std::ptrdiff_t(nf), state_.end(), kSentinel);
    touched_.clear();
    full_ = true;
    auto run = [&](std::size_t lo, std::size_t hi) {
#if defined(__x86_64__) && defined(__GNUC__)
        if (cpu_has_avx2()) return facing_states_avx2(mesh.facing.data() + lo, hi - lo, filter_, state_.data() + lo);
#endif
        facing_states_scalar(mesh.facing.data() + lo, hi - lo, filter_, state_.data() + lo);
    };
    const std::size_t parts = std::size_t(std::clamp(threads, 1, 64));
    if (parts == 1 || nf < 65536) return run(0, nf);
    std::vector<std::thread> pool;
    const std::size_t step = (nf / parts + 63) & ~std::size_t(63);  // cache-line aligned parts
    for (std::size_t i = 1; i < parts; ++i)
        if (i * step < nf) pool.emplace_back(run, i * step, std::min(nf, (i + 1) * step));
    run(0, std::min(nf, step));
    for (auto& t : pool) t.join();
}

float FaceFacing::signed_distance(std::uint32_t f) const { return filter_.signed_distance(mesh_->facing[f]); }

std::uint8_t FaceFacing::filter(std::uint32_t f) const { return filter_(mesh_->facing[f]); }

std::uint8_t FaceFacing::resolve(std::uint32_t f) const {
    std::uint8_t s = full_ ? kUnknown : filter(f);
    if (s == kUnknown) {
        const MeshTopology& m = *mesh_;
        const auto& v = m.faces[f];
        ++exact_;
        s = orient_eye(camera_, m.positions[v[0]], m.positions[v[1]], m.positions[v[2]]) > 0 ? kFront : kBack;
    }
    state_[f] = s;
    if (!full_) touched_.push_back(f);
    return s;
}

std::vector<std::uint8_t> FaceFacing::all() const {
    std::vector<std::uint8_t> out(size());
    for (std::uint32_t f = 0; f < out.size(); ++f) out[f] = (*this)[f];
    return out;
}

}  // namespace inkline
