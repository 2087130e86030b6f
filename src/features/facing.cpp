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
    const glm::dvec3 v = ortho ? -camera.forward() : camera.eye() - mesh.facing_origin;
    const double e[3] = {v.x, v.y, v.z};
    bind(mesh, e, ortho ? 0.0 : 1.0);
}

void FacingFilter::bind(const MeshTopology& mesh, const double e[3], double wv) {
    const bool ortho = wv == 0.0;
    ex = float(e[0]);
    ey = float(e[1]);
    ez = float(e[2]);
    w = ortho ? 0.0f : 1.0f;
    const double l1 = std::abs(e[0]) + std::abs(e[1]) + std::abs(e[2]);
    bound = float(0x1p-18 * (l1 + (ortho ? 0.0 : mesh.facing_radius)) + 1e-36);
    if (!std::isfinite(ex) || !std::isfinite(ey) || !std::isfinite(ez) || !std::isfinite(bound))
        bound = INFINITY;  // out of float range: every face goes to the exact test
}

void FaceFacing::bind(const MeshTopology& mesh, const Camera& camera) {
    ++generation_;
    mesh_ = &mesh;
    camera_ = camera;
    exact_ = 0;
    filter_.bind(mesh, camera);
}

void FaceFacing::begin_lazy(const MeshTopology& mesh, const Camera& camera) {
    const std::size_t nf = mesh.face_count();
    if (full_ || state_.size() != nf + kPad || mesh_ != &mesh) {
        state_.assign(nf + kPad, kSentinel);
        std::fill(state_.begin(), state_.begin() + std::ptrdiff_t(nf), kUnknown);
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

// The band's rows as select() writes them: n faces so far; every row at least n + 8 long before
// a group of 8 is stored (a group is stored whole, its selected faces first).
struct BandRows {
    std::vector<std::uint32_t>& ids;
    std::vector<float>&nx, &ny, &nz, &d;
    std::size_t n = 0;
    void room(std::size_t more) {
        if (n + more <= ids.size()) return;
        const std::size_t len = std::max<std::size_t>(2 * ids.size(), n + more + 1024);
        ids.resize(len);
        for (auto* row : {&nx, &ny, &nz, &d}) row->resize(len);
    }
};

// Faces [f0, f1) whose float distance to the eye is not above limit (NaN planes included),
// appended to the rows. With `front`: the bit of each face in [f0, f1) (f0 a multiple of 64) set
// where its float distance is above zero, cleared elsewhere.
void band_rows_scalar(const MeshTopology::FacingPlane* p, std::uint32_t f0, std::uint32_t f1, const FacingFilter& flt,
                      float limit, BandRows& rows, std::uint64_t* front) {
    for (std::uint32_t f = f0; f < f1; ++f) {
        const float det = flt.signed_distance(p[f]);
        if (!(std::abs(det) > limit)) {
            rows.room(1);
            const std::size_t i = rows.n++;
            rows.ids[i] = f, rows.nx[i] = p[f].nx, rows.ny[i] = p[f].ny, rows.nz[i] = p[f].nz, rows.d[i] = p[f].d;
        }
        if (front) {
            const std::uint64_t m = std::uint64_t(1) << (f & 63);
            front[f >> 6] = det > 0.0f ? (front[f >> 6] | m) : (front[f >> 6] & ~m);
        }
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
// Lane permutations that move the lanes of each 8-bit mask to the front, in order.
struct PackTable {
    alignas(32) std::uint32_t lanes[256][8];
    constexpr PackTable() : lanes{} {
        for (unsigned m = 0; m < 256; ++m) {
            unsigned k = 0;
            for (unsigned j = 0; j < 8; ++j)
                if ((m >> j) & 1) lanes[m][k++] = j;
            for (; k < 8; ++k) lanes[m][k] = 0;
        }
    }
};
constexpr PackTable kPack;

// band_rows_scalar's rows and bits, eight faces a step: the selected lanes of the transposed
// planes (the rows' own layout) and of the ids packed to the front and stored whole.
__attribute__((target("avx2,bmi2"))) void band_rows_avx2(const MeshTopology::FacingPlane* p, std::uint32_t f0,
                                                         std::uint32_t nf, const FacingFilter& flt, float limit,
                                                         BandRows& rows, std::uint64_t* front) {
    Eye8 eye;
    load_eye8(flt, eye);
    const __m256 lim = _mm256_set1_ps(limit), zero = _mm256_setzero_ps();
    const __m256 abs_mask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    std::uint32_t f = f0;
    std::uint64_t word = 0;  // front bits of the current 64 faces
    for (; f + 8 <= nf; f += 8) {
        Planes8 p8;
        load_planes8(&p[f].nx, p8);
        __m256 det;
        eye_distance8(p8, eye, det);
        if (front) {
            word |= std::uint64_t(unsigned(_mm256_movemask_ps(_mm256_cmp_ps(det, zero, _CMP_GT_OQ)))) << (f & 56);
            if ((f & 56) == 56) front[f >> 6] = word, word = 0;
        }
        const unsigned m = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(_mm256_and_ps(det, abs_mask), lim, _CMP_NGT_UQ)));
        if (!m) continue;
        if (rows.n + 8 > rows.ids.size()) rows.room(4096);
        const __m256i idx = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPack.lanes[m]));
        const std::size_t n = rows.n;
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(rows.ids.data() + n),
                            _mm256_permutevar8x32_epi32(_mm256_add_epi32(_mm256_set1_epi32(int(f)), lane), idx));
        _mm256_storeu_ps(rows.nx.data() + n, _mm256_permutevar8x32_ps(p8.nx, idx));
        _mm256_storeu_ps(rows.ny.data() + n, _mm256_permutevar8x32_ps(p8.ny, idx));
        _mm256_storeu_ps(rows.nz.data() + n, _mm256_permutevar8x32_ps(p8.nz, idx));
        _mm256_storeu_ps(rows.d.data() + n, _mm256_permutevar8x32_ps(p8.d, idx));
        rows.n = n + unsigned(__builtin_popcount(m));
    }
    if (front && (f & 63)) {  // a word begun: its first faces from here, the rest by the scalar loop
        const std::uint64_t keep = (std::uint64_t(1) << (f & 63)) - 1;
        front[f >> 6] = (front[f >> 6] & ~keep) | word;
    }
    band_rows_scalar(p, f, nf, flt, limit, rows, front);
}
#endif

// The band's front bits (8 faces a byte) and check positions, for positions [i0, n).
void band_states_scalar(const float* nx, const float* ny, const float* nz, const float* d, std::size_t i0,
                        std::size_t n, const FacingFilter& now, const FacingFilter& before, std::uint8_t* front,
                        std::vector<std::uint32_t>& check) {
    for (std::size_t i = i0; i < n; ++i) {
        const MeshTopology::FacingPlane p{nx[i], ny[i], nz[i], d[i]};
        const std::uint8_t a = now(p), b = before(p);
        const std::uint8_t m = std::uint8_t(1u << (i & 7));
        front[i >> 3] = a == FaceFacing::kFront ? std::uint8_t(front[i >> 3] | m) : std::uint8_t(front[i >> 3] & ~m);
        if (a != b || a == FaceFacing::kUnknown) check.push_back(std::uint32_t(i));
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
// The same 8 faces a step from the four rows (the same products and sums in the same order as
// FacingFilter::signed_distance, no FMA, so the same floats).
__attribute__((target("avx2,bmi2"))) std::size_t band_states_avx2(const float* nx, const float* ny, const float* nz,
                                                                  const float* d, std::size_t n,
                                                                  const FacingFilter& now, const FacingFilter& before,
                                                                  std::uint8_t* front, std::vector<std::uint32_t>& check) {
    Eye8 eye_now, eye_before;
    load_eye8(now, eye_now);
    load_eye8(before, eye_before);
    const __m256 ab = _mm256_set1_ps(now.bound), anb = _mm256_set1_ps(-now.bound);
    const __m256 bb = _mm256_set1_ps(before.bound), bnb = _mm256_set1_ps(-before.bound);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const Planes8 p8{_mm256_loadu_ps(nx + i), _mm256_loadu_ps(ny + i), _mm256_loadu_ps(nz + i), _mm256_loadu_ps(d + i)};
        __m256 da, db;
        eye_distance8(p8, eye_now, da);
        eye_distance8(p8, eye_before, db);
        const unsigned fa = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(da, ab, _CMP_GT_OQ)));
        const unsigned ka = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(da, anb, _CMP_NLT_UQ)));  // not back
        const unsigned fb = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(db, bb, _CMP_GT_OQ)));
        const unsigned kb = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(db, bnb, _CMP_NLT_UQ)));
        // states differ, or "now" undecided (not back and not front)
        unsigned odd = (fa ^ fb) | (ka ^ kb) | (ka & ~fa);
        front[i >> 3] = std::uint8_t(fa);
        while (odd) {
            check.push_back(std::uint32_t(i + unsigned(__builtin_ctz(odd))));
            odd &= odd - 1;
        }
    }
    return i;
}

// Scatters the band's front bits into the words of the face bit set (pdep per word).
__attribute__((target("bmi2"))) void band_words_bmi2(const std::uint32_t* words, const std::uint64_t* masks,
                                                     std::size_t nw, const std::uint8_t* front, std::uint64_t* bits) {
    std::size_t o = 0;  // band position of the word's first face
    for (std::size_t k = 0; k < nw; ++k) {
        const std::uint64_t mask = masks[k];
        std::uint64_t lo, hi;
        std::memcpy(&lo, front + (o >> 3), 8);
        std::memcpy(&hi, front + (o >> 3) + 8, 8);
        const unsigned sh = unsigned(o & 7);
        const std::uint64_t run = sh ? (lo >> sh) | (hi << (64 - sh)) : lo;
        bits[words[k]] = (bits[words[k]] & ~mask) | _pdep_u64(run, mask);
        o += std::size_t(__builtin_popcountll(mask));
    }
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

void FaceBlocks::build(const MeshTopology& mesh) {
    start(mesh);
    build_range(0, bounds_.size());
}

void FaceBlocks::start(const MeshTopology& mesh) {
    mesh_ = &mesh;
    edges_tried_ = false;
    nf_ = mesh.face_count();
    bounds_.assign((nf_ + kFaces - 1) / kFaces, Bounds{});
    edge_begin_.clear();
    nbr_begin_.clear();
    nbr_.clear();
}

void FaceBlocks::build_range(std::size_t b0, std::size_t b1) {
    const MeshTopology& mesh = *mesh_;
    for (std::size_t b = b0; b < b1; ++b) {
        Bounds& r = bounds_[b];
        const std::size_t f0 = b * kFaces, f1 = std::min(nf_, f0 + kFaces);
        for (int i = 0; i < 4; ++i) r.lo[i] = INFINITY, r.hi[i] = -INFINITY;
        bool nan = false;
#if defined(__x86_64__) && defined(__GNUC__)
        // Four faces a step into four accumulators (min and max are exact, so any order gives
        // the same ranges, up to the sign of zero; a NaN plane marks the block, whatever the
        // ranges say): the chains of dependent min/max no longer bound the speed.
        __m128 lo = _mm_set1_ps(INFINITY), hi = _mm_set1_ps(-INFINITY), un = _mm_setzero_ps();
        __m128 lo1 = lo, lo2 = lo, lo3 = lo, hi1 = hi, hi2 = hi, hi3 = hi;
        std::size_t f = f0;
        for (; f + 4 <= f1; f += 4) {
            const float* q = &mesh.facing[f].nx;  // FacingPlane is 16-byte aligned
            const __m128 p0 = _mm_load_ps(q), p1 = _mm_load_ps(q + 4), p2 = _mm_load_ps(q + 8), p3 = _mm_load_ps(q + 12);
            lo = _mm_min_ps(lo, p0), lo1 = _mm_min_ps(lo1, p1), lo2 = _mm_min_ps(lo2, p2), lo3 = _mm_min_ps(lo3, p3);
            hi = _mm_max_ps(hi, p0), hi1 = _mm_max_ps(hi1, p1), hi2 = _mm_max_ps(hi2, p2), hi3 = _mm_max_ps(hi3, p3);
            un = _mm_or_ps(un, _mm_or_ps(_mm_cmpunord_ps(p0, p1), _mm_cmpunord_ps(p2, p3)));
        }
        for (; f < f1; ++f) {
            const __m128 p = _mm_load_ps(&mesh.facing[f].nx);
            lo = _mm_min_ps(lo, p);
            hi = _mm_max_ps(hi, p);
            un = _mm_or_ps(un, _mm_cmpunord_ps(p, p));
        }
        lo = _mm_min_ps(_mm_min_ps(lo, lo1), _mm_min_ps(lo2, lo3));
        hi = _mm_max_ps(_mm_max_ps(hi, hi1), _mm_max_ps(hi2, hi3));
        _mm_storeu_ps(r.lo, lo);
        _mm_storeu_ps(r.hi, hi);
        nan = _mm_movemask_ps(un) != 0;
#else
        for (std::size_t f = f0; f < f1; ++f) {
            const auto& p = mesh.facing[f];
            const float v[4] = {p.nx, p.ny, p.nz, p.d};
            for (int i = 0; i < 4; ++i) {
                nan = nan || std::isnan(v[i]);
                r.lo[i] = std::min(r.lo[i], v[i]);
                r.hi[i] = std::max(r.hi[i], v[i]);
            }
        }
#endif
        if (nan || f0 == f1) r.lo[0] = r.hi[0] = NAN;  // never decided as a whole
    }
}

void FaceBlocks::build_edges() {
    // Edges are numbered in the order of their first face (topology.cpp); anything else: no
    // edge ranges.
    const MeshTopology& mesh = *mesh_;
    const std::size_t ne = mesh.edge_count(), nb = bounds_.size();
    edges_tried_ = true;
    edge_begin_.assign(nb + 1, std::uint32_t(ne));
    nbr_begin_.assign(nb + 1, 0);
    std::vector<std::uint32_t> list, seen(nb, UINT32_MAX);  // seen[k]: last block that listed k
    std::size_t e = 0;
    std::uint32_t last = 0;
    for (std::size_t b = 0; b < nb; ++b) {
        edge_begin_[b] = std::uint32_t(e);
        nbr_begin_[b] = std::uint32_t(nbr_.size());
        list.clear();
        bool border = false;
        const std::uint32_t end = std::uint32_t(std::min(nf_, (b + 1) * kFaces));
        for (; e < ne; ++e) {
            const auto& ef = mesh.edge_face[e];
            if (ef[0] >= end) break;
            if (ef[0] < last) {  // not numbered by first face
                edge_begin_.clear();
                nbr_begin_.clear();
                nbr_.clear();
                return;
            }
            last = ef[0];
            if (ef[1] == kNoFace) {
                if (!border) list.push_back(kBorderBlock), border = true;
                continue;
            }
            const std::uint32_t nbk = ef[1] / kFaces;
            if (nbk != b && seen[nbk] != b) seen[nbk] = std::uint32_t(b), list.push_back(nbk);
        }
        nbr_.insert(nbr_.end(), list.begin(), list.end());
    }
    if (e != ne) {  // edges whose first face is out of range
        edge_begin_.clear();
        nbr_begin_.clear();
        nbr_.clear();
        return;
    }
    nbr_begin_[nb] = std::uint32_t(nbr_.size());
    nbr_.shrink_to_fit();
}

std::size_t FaceBlocks::bytes() const {
    return bounds_.capacity() * sizeof(Bounds) +
           (edge_begin_.capacity() + nbr_begin_.capacity() + nbr_.capacity()) * sizeof(std::uint32_t);
}

// The filter's float distance is fl(fl(fl(nx ex) + fl(ny ey)) + fl(nz ez)) - fl(w d); its real
// value over the block lies in the interval sum of the four products' ranges (computed in double:
// the products of two floats are exact, the sums err by 2^-52 relative), and the float
// evaluation errs from it by at most 4 * 2^-24 * (|nx ex| + |ny ey| + |nz ez| + |w d|); the range
// is widened by 2^-20 times that sum's bound.
void FaceBlocks::distance_range(std::size_t b, const FacingFilter& f, double& lo, double& hi) const {
    const Bounds& r = bounds_[b];
    const double e[4] = {f.ex, f.ey, f.ez, -double(f.w)};
    double l = 0.0, h = 0.0, mag = 0.0;
    for (int i = 0; i < 4; ++i) {
        const double a = double(r.lo[i]) * e[i], c = double(r.hi[i]) * e[i];
        l += std::min(a, c);
        h += std::max(a, c);
        mag += std::max(std::abs(a), std::abs(c));
    }
    const double slack = mag * 0x1p-20;
    if (std::isnan(l) || std::isnan(h) || std::isnan(slack)) {
        lo = hi = NAN;
        return;
    }
    lo = l - slack;
    hi = h + slack;
}

std::uint8_t FaceBlocks::classify(std::size_t b, const FacingFilter& f) const {
    double lo, hi;
    distance_range(b, f, lo, hi);
    if (lo > double(f.bound)) return FaceFacing::kFront;  // every det > bound
    if (hi < -double(f.bound)) return FaceFacing::kBack;  // every det < -bound
    return FaceFacing::kUnknown;                          // (also NaN)
}

bool BlockEdges::build(const MeshTopology& mesh) {
    mesh_ = &mesh;
    nf_ = mesh.face_count();
    const std::size_t ne = mesh.edge_count(), nb = (nf_ + kFaces - 1) / kFaces;
    auto fail = [&] {
        index_.clear(), owned_.clear(), edge_begin_.clear(), base2_.clear(), esc_begin_.clear();
        esc_self_.clear(), esc_far_.clear(), esc_corner_.clear();
        return false;
    };
    if (ne >= kCheck || nf_ >= kCheck) return fail();
    index_.resize(nb * 3 * kFaces);
    for (std::size_t b = 0; b < nb; ++b)
        for (std::uint32_t k = 0; k < 3; ++k)
            for (std::uint32_t j = 0; j < kFaces; ++j) index_[(3 * b + k) * kFaces + j] = std::uint8_t(j);
    owned_.assign(3 * nb, 0);
    edge_begin_.assign(nb + 1, std::uint32_t(ne));
    base2_.assign(nb, 0);
    esc_begin_.assign(nb + 1, 0);
    esc_self_.clear(), esc_far_.clear(), esc_corner_.clear();
    struct Far {
        std::uint32_t face, corner;  // neighbour, k * 64 + j
    };
    std::vector<Far> far;
    std::size_t e = 0;
    std::uint64_t last_corner = 0;
    for (std::size_t b = 0; b < nb; ++b) {
        const std::uint32_t base = std::uint32_t(b * kFaces), end = std::uint32_t(std::min(nf_, b * kFaces + kFaces));
        edge_begin_[b] = std::uint32_t(e);
        esc_begin_[b] = std::uint32_t(esc_self_.size());
        far.clear();
        for (; e < ne; ++e) {
            const auto [f, n] = mesh.edge_face[e];
            if (f >= end) break;
            if (f < base) return fail();
            // The corner that numbers e: the first corner of f on it; edge order must be corner order.
            const auto& fe = mesh.face_edges[f].edge;
            const std::uint32_t k = fe[0] == e ? 0 : fe[1] == e ? 1 : fe[2] == e ? 2 : 3;
            const std::uint64_t corner = 3 * std::uint64_t(f) + k;
            if (k == 3 || (e > 0 && corner <= last_corner)) return fail();
            last_corner = corner;
            const std::uint32_t j = f - base, bit = 3 * j + k;
            owned_[3 * b + bit / 64] |= std::uint64_t(1) << (bit % 64);
            if (n == kNoFace) continue;  // borders: never a silhouette
            if (n > f && n < base + 128) index_[(3 * b + k) * kFaces + j] = std::uint8_t(n - base);
            else far.push_back({n, k * kFaces + j});
        }
        // The second window: the 128 faces from a far neighbour that hold the most of them.
        std::sort(far.begin(), far.end(), [](const Far& a, const Far& c) { return a.face < c.face; });
        std::size_t best = 0, at = 0;
        for (std::size_t i = 0, i1 = 0; i < far.size(); ++i) {
            while (i1 < far.size() && far[i1].face < std::uint64_t(far[i].face) + 128) ++i1;
            if (i1 - i > best) best = i1 - i, at = i;
        }
        const std::uint32_t b2 = far.empty() ? base : std::min(far[at].face, std::uint32_t(nf_ - 1));
        base2_[b] = b2;
        std::sort(far.begin(), far.end(), [](const Far& a, const Far& c) { return a.corner < c.corner; });
        for (const Far& x : far) {
            const std::uint32_t j = x.corner % kFaces, k = x.corner / kFaces;
            if (x.face > base + j && x.face >= b2 && x.face < std::uint64_t(b2) + 128) {
                index_[(3 * b + k) * kFaces + j] = std::uint8_t(128 + (x.face - b2));
            } else {  // (also a neighbour that is the face itself: only its exact test differs)
                esc_self_.push_back(base + j);
                esc_far_.push_back(x.face);
                esc_corner_.push_back(std::uint8_t(x.corner));
            }
        }
    }
    if (e != ne) return fail();
    esc_begin_[nb] = std::uint32_t(esc_self_.size());
    esc_self_.shrink_to_fit(), esc_far_.shrink_to_fit(), esc_corner_.shrink_to_fit();
    return true;
}

std::size_t BlockEdges::bytes() const {
    return index_.capacity() + esc_corner_.capacity() + owned_.capacity() * 8 +
           (edge_begin_.capacity() + base2_.capacity() + esc_begin_.capacity() + esc_self_.capacity() +
            esc_far_.capacity()) * 4;
}

namespace {
bool has_avx512_vbmi() {
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool has = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                            __builtin_cpu_supports("avx512vbmi") && __builtin_cpu_supports("bmi2");
    return has;
#else
    return false;
#endif
}
}  // namespace

bool BlockEdges::has_simd() { return has_avx512_vbmi() || cpu_has_avx2(); }

namespace {

// Escape i is a candidate where its face is decided and differs from its neighbour (an undecided
// face makes all its edges candidates anyway, BlockEdges::scan_block).
inline bool escape_candidate(std::uint8_t a, std::uint8_t c) { return a != c && !(a & FaceFacing::kUnknown); }

#if defined(__x86_64__) && defined(__GNUC__)
#define INKLINE_AVX512 __attribute__((target("avx512f,avx512bw,avx512vbmi,bmi2")))
// Sixteen escapes a step: both states gathered (as 32-bit words, masked to their low byte).
INKLINE_AVX512 void escape_bits_avx512(const std::uint8_t* st, const std::uint32_t* self, const std::uint32_t* far,
                                       std::size_t n, std::uint16_t* bits) {
    const int* s = reinterpret_cast<const int*>(st);
    const __m512i low = _mm512_set1_epi32(0xff), unknown = _mm512_set1_epi32(FaceFacing::kUnknown);
    for (std::size_t i = 0; i < n; i += 16) {
        const __mmask16 live = n - i >= 16 ? __mmask16(0xffff) : __mmask16((1u << (n - i)) - 1);
        const __m512i fa = _mm512_maskz_loadu_epi32(live, self + i), fc = _mm512_maskz_loadu_epi32(live, far + i);
        const __m512i a = _mm512_and_si512(_mm512_mask_i32gather_epi32(_mm512_setzero_si512(), live, fa, s, 1), low);
        const __m512i c = _mm512_and_si512(_mm512_mask_i32gather_epi32(_mm512_setzero_si512(), live, fc, s, 1), low);
        bits[i / 16] = std::uint16_t(_mm512_mask_cmpneq_epi32_mask(live, a, c) & ~_mm512_test_epi32_mask(a, unknown));
    }
}

// Corner masks (corner-major, bit j of word k) of one block: neighbour's state differs from the
// face's, both decided (sure), or the neighbour undecided (check).
// Returns false (all masks zero, the index not read) where both windows hold one decided state.
INKLINE_AVX512 bool block_masks_avx512(const std::uint8_t* st, std::uint32_t base, std::uint32_t base2,
                                       const std::uint8_t* index, std::uint64_t sure[3], std::uint64_t check[3],
                                       std::uint64_t& undecided) {
    const __m512i one = _mm512_set1_epi8(FaceFacing::kUnknown);
    const __m512i t0 = _mm512_loadu_si512(st + base), t1 = _mm512_loadu_si512(st + base + 64);
    const __m512i u0 = _mm512_loadu_si512(st + base2), u1 = _mm512_loadu_si512(st + base2 + 64);
    undecided = _mm512_test_epi8_mask(t0, one);
    const __m512i s = _mm512_set1_epi8(char(st[base]));
    if (!(st[base] & FaceFacing::kUnknown) &&
        (_mm512_cmpeq_epi8_mask(t0, s) & _mm512_cmpeq_epi8_mask(t1, s) & _mm512_cmpeq_epi8_mask(u0, s) &
         _mm512_cmpeq_epi8_mask(u1, s)) == ~std::uint64_t(0)) {
        sure[0] = sure[1] = sure[2] = check[0] = check[1] = check[2] = 0;
        return false;
    }
    for (int k = 0; k < 3; ++k) {
        const __m512i ix = _mm512_loadu_si512(index + 64 * k);
        const __m512i v = _mm512_mask_blend_epi8(_mm512_movepi8_mask(ix), _mm512_permutex2var_epi8(t0, ix, t1),
                                                 _mm512_permutex2var_epi8(u0, ix, u1));
        const std::uint64_t differ = _mm512_cmpneq_epi8_mask(t0, v), vu = _mm512_test_epi8_mask(v, one);
        sure[k] = differ & ~vu & ~undecided;
        check[k] = differ & vu & ~undecided;
    }
    return true;
}
#endif

#if defined(__x86_64__) && defined(__GNUC__)
#define INKLINE_AVX2_BMI2 __attribute__((target("avx2,bmi2")))
// Bit `shift` of each byte's state (7: bit 0, 6: bit 1) moved to its top bit, one bit per byte.
INKLINE_AVX2 inline std::uint32_t state_bits(__m256i v, int shift) {
    return std::uint32_t(_mm256_movemask_epi8(_mm256_slli_epi16(v, shift)));
}
// The same masks with AVX2, which has no byte permutation across 128 or 256 entries: the two
// windows' 256 states as two 256-bit planes (their bit 0 and bit 1, one bit per face), and each
// index's bits looked up in them (its byte by two in-lane shuffles, its bit by a mask): the same
// states, so the same masks.
INKLINE_AVX2_BMI2 bool block_masks_avx2(const std::uint8_t* st, std::uint32_t base, std::uint32_t base2,
                                   const std::uint8_t* index, std::uint64_t sure[3], std::uint64_t check[3],
                                   std::uint64_t& undecided) {
    __m256i w[8];
    for (int i = 0; i < 4; ++i) {
        w[i] = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(st + base + 32 * i));
        w[4 + i] = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(st + base2 + 32 * i));
    }
    undecided = std::uint64_t(state_bits(w[0], 7)) | std::uint64_t(state_bits(w[1], 7)) << 32;  // kUnknown is bit 0 (and the sentinel's)
    const std::uint8_t s0 = st[base];
    if (!(s0 & FaceFacing::kUnknown)) {
        const __m256i s = _mm256_set1_epi8(char(s0));
        __m256i same = _mm256_cmpeq_epi8(w[0], s);
        for (int i = 1; i < 8; ++i) same = _mm256_and_si256(same, _mm256_cmpeq_epi8(w[i], s));
        if (_mm256_movemask_epi8(same) == -1) {
            sure[0] = sure[1] = sure[2] = check[0] = check[1] = check[2] = 0;
            return false;
        }
    }
    std::uint32_t plane0[8], plane1[8];  // (only for blocks whose index is read)
    for (int i = 0; i < 8; ++i) plane0[i] = state_bits(w[i], 7), plane1[i] = state_bits(w[i], 6);
    const __m256i t0 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(plane0));
    const __m256i t1 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(plane1));
    const __m256i t0lo = _mm256_permute2x128_si256(t0, t0, 0x00), t0hi = _mm256_permute2x128_si256(t0, t0, 0x11);
    const __m256i t1lo = _mm256_permute2x128_si256(t1, t1, 0x00), t1hi = _mm256_permute2x128_si256(t1, t1, 0x11);
    const __m256i bit = _mm256_setr_epi8(1, 2, 4, 8, 16, 32, 64, -128, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2, 4, 8, 16, 32, 64, -128,
                                         0, 0, 0, 0, 0, 0, 0, 0);
    const __m256i seven = _mm256_set1_epi8(7), low5 = _mm256_set1_epi8(31);
    std::uint32_t d[2], u[2];
    for (int k = 0; k < 3; ++k) {
        for (int h = 0; h < 2; ++h) {
            const __m256i ix = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index + 64 * k + 32 * h));
            const __m256i byte = _mm256_and_si256(_mm256_srli_epi16(ix, 3), low5);  // 0..31: its byte in a plane
            const __m256i upper = _mm256_slli_epi16(byte, 3);  // bit 4 (the upper 16 bytes) to the top bit
            const __m256i r0 = _mm256_blendv_epi8(_mm256_shuffle_epi8(t0lo, byte), _mm256_shuffle_epi8(t0hi, byte), upper);
            const __m256i r1 = _mm256_blendv_epi8(_mm256_shuffle_epi8(t1lo, byte), _mm256_shuffle_epi8(t1hi, byte), upper);
            const __m256i m = _mm256_shuffle_epi8(bit, _mm256_and_si256(ix, seven));
            const std::uint32_t v0 = std::uint32_t(_mm256_movemask_epi8(_mm256_cmpeq_epi8(_mm256_and_si256(r0, m), m)));
            const std::uint32_t v1 = std::uint32_t(_mm256_movemask_epi8(_mm256_cmpeq_epi8(_mm256_and_si256(r1, m), m)));
            d[h] = (v0 ^ plane0[h]) | (v1 ^ plane1[h]);  // the face's state (the first window's face j) differs
            u[h] = v0;
        }
        const std::uint64_t differ = std::uint64_t(d[0]) | std::uint64_t(d[1]) << 32;
        const std::uint64_t vu = std::uint64_t(u[0]) | std::uint64_t(u[1]) << 32;
        sure[k] = differ & ~vu & ~undecided;
        check[k] = differ & vu & ~undecided;
    }
    return true;
}
#endif

bool block_masks_scalar(const std::uint8_t* st, std::uint32_t base, std::uint32_t base2, const std::uint8_t* index,
                        std::uint64_t sure[3], std::uint64_t check[3], std::uint64_t& undecided) {
    undecided = 0;
    bool uniform = !(st[base] & FaceFacing::kUnknown);
    for (std::uint32_t j = 0; j < 128; ++j) uniform = uniform && st[base + j] == st[base] && st[base2 + j] == st[base];
    if (uniform) {
        sure[0] = sure[1] = sure[2] = check[0] = check[1] = check[2] = 0;
        return false;
    }
    for (std::uint32_t j = 0; j < 64; ++j) undecided |= std::uint64_t(st[base + j] & FaceFacing::kUnknown) << j;
    for (int k = 0; k < 3; ++k) {
        sure[k] = check[k] = 0;
        for (std::uint32_t j = 0; j < 64; ++j) {
            const std::uint8_t i = index[64 * k + j], a = st[base + j];
            const std::uint8_t v = i < 128 ? st[base + i] : st[base2 + (i - 128)];
            const std::uint64_t bit = std::uint64_t(a != v && !(a & FaceFacing::kUnknown)) << j;
            (v & FaceFacing::kUnknown ? check : sure)[k] |= bit;
        }
    }
    return true;
}

#if defined(__x86_64__) && defined(__GNUC__)
// The corner-major masks (bit j of word k) interleaved to corner order (bit 3 j + k of three
// words), then compressed to the owned corners (pext): bit r of word w is the edge numbered
// r-th in that word's corners.
INKLINE_AVX2_BMI2 inline void corner_order(const std::uint64_t m[3], std::uint64_t out[3]) {
    constexpr std::uint64_t k0 = 0x9249249249249249ull, k1 = k0 << 1, k2 = k0 << 2;  // bits = 0, 1, 2 mod 3
    out[0] = _pdep_u64(m[0], k0) | _pdep_u64(m[1], k1) | _pdep_u64(m[2], k2);
    out[1] = _pdep_u64(m[0] >> 22, k2) | _pdep_u64(m[1] >> 21, k0) | _pdep_u64(m[2] >> 21, k1);  // bit 64: j 21, k 1
    out[2] = _pdep_u64(m[0] >> 43, k1) | _pdep_u64(m[1] >> 43, k2) | _pdep_u64(m[2] >> 42, k0);  // bit 128: j 42, k 2
}
static_assert(BlockEdges::kCheck == 1u << 31);
INKLINE_AVX2_BMI2 void emit_bmi2(const std::uint64_t sure[3], const std::uint64_t check[3], const std::uint64_t owned[3],
                              std::uint32_t e0, std::vector<std::uint32_t>& out) {
    std::uint64_t all[3], chk[3];
    const std::uint64_t any[3] = {sure[0] | check[0], sure[1] | check[1], sure[2] | check[2]};
    corner_order(any, all);
    corner_order(check, chk);
    std::uint32_t buf[3 * 64], n = 0;
    for (int w = 0; w < 3; ++w) {
        for (std::uint64_t r = _pext_u64(all[w], owned[w]), c = _pext_u64(chk[w], owned[w]); r; r &= r - 1) {
            const unsigned i = unsigned(__builtin_ctzll(r));
            buf[n++] = (e0 + i) | (std::uint32_t((c >> i) & 1) << 31);  // (BlockEdges::kCheck)
        }
        e0 += std::uint32_t(__builtin_popcountll(owned[w]));
    }
    out.insert(out.end(), buf, buf + n);
}
#endif

}  // namespace

void BlockEdges::escape_bits(const std::uint8_t* st, std::uint32_t b0, std::uint32_t b1, std::vector<std::uint16_t>& bits,
                             bool simd) const {
    const std::size_t i0 = esc_begin_[b0], n = esc_begin_[b1] - i0;
    bits.assign((n + 15) / 16, 0);
#if defined(__x86_64__) && defined(__GNUC__)
    if (simd && has_avx512_vbmi()) return escape_bits_avx512(st, esc_self_.data() + i0, esc_far_.data() + i0, n, bits.data());
#endif
    for (std::size_t i = 0; i < n; ++i)
        bits[i / 16] |= std::uint16_t(escape_candidate(st[esc_self_[i0 + i]], st[esc_far_[i0 + i]]) << (i % 16));
}

bool BlockEdges::scan_block(const std::uint8_t* st, std::uint32_t b, const std::uint16_t* esc, std::uint32_t esc0,
                            std::vector<std::uint32_t>& out, bool simd) const {
    const std::uint32_t base = b * kFaces;
    const std::uint8_t* index = index_.data() + std::size_t(b) * 3 * kFaces;
    std::uint64_t sure[3], check[3], undecided;
#if defined(__x86_64__) && defined(__GNUC__)
    if (b + 8 < base2_.size()) {  // the second window is elsewhere in the states: fetch it ahead
        _mm_prefetch(reinterpret_cast<const char*>(st + base2_[b + 8]), _MM_HINT_T0);
        _mm_prefetch(reinterpret_cast<const char*>(st + base2_[b + 8] + 64), _MM_HINT_T0);
        _mm_prefetch(reinterpret_cast<const char*>(st + base2_[b + 8] + 127), _MM_HINT_T0);
        for (int i = 0; i < 3; ++i) _mm_prefetch(reinterpret_cast<const char*>(index + 8 * 3 * kFaces + 64 * i), _MM_HINT_T0);
    }
    const bool read = simd && has_avx512_vbmi() ? block_masks_avx512(st, base, base2_[b], index, sure, check, undecided)
                      : simd && cpu_has_avx2()  ? block_masks_avx2(st, base, base2_[b], index, sure, check, undecided)
                                                : block_masks_scalar(st, base, base2_[b], index, sure, check, undecided);
#else
    const bool read = block_masks_scalar(st, base, base2_[b], index, sure, check, undecided);
#endif
    // Escapes: the rare candidates among them set their corner's bit.
    for (std::uint32_t i = esc_begin_[b]; i < esc_begin_[b + 1]; ++i) {
        const std::uint32_t r = i - esc0;
        if (!((esc[r / 16] >> (r % 16)) & 1)) continue;
        const std::uint32_t c = esc_corner_[i], k = c / kFaces, j = c % kFaces;
        ((st[esc_far_[i]] & FaceFacing::kUnknown) ? check : sure)[k] |= std::uint64_t(1) << j;
    }
    // Undecided faces (past the last face: the sentinel, not a face): every interior edge they
    // number is checked.
    const std::uint32_t live = std::uint32_t(std::min<std::size_t>(kFaces, nf_ - base));
    if (live < 64) undecided &= (std::uint64_t(1) << live) - 1;
    for (std::uint64_t u = undecided; u; u &= u - 1) {
        const std::uint32_t j = std::uint32_t(__builtin_ctzll(u));
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t bit = 3 * j + k;
            if (!((owned_[3 * b + bit / 64] >> (bit % 64)) & 1)) continue;
            if (mesh_->face_edges[base + j].face[k] == kNoFace) continue;
            check[k] |= std::uint64_t(1) << j;
        }
    }
    if (!((sure[0] | sure[1] | sure[2] | check[0] | check[1] | check[2]))) return read;
    // Corner order (bit 3 j + k), then the owned corners' ranks: edge ids.
    const std::uint64_t* owned = owned_.data() + 3 * std::size_t(b);
#if defined(__x86_64__) && defined(__GNUC__)
    if (simd && cpu_has_avx2()) {
        emit_bmi2(sure, check, owned, edge_begin_[b], out);
        return read;
    }
#endif
    const std::uint32_t before[3] = {0, std::uint32_t(__builtin_popcountll(owned[0])),
                                     std::uint32_t(__builtin_popcountll(owned[0]) + __builtin_popcountll(owned[1]))};
    for (std::uint64_t any = sure[0] | sure[1] | sure[2] | check[0] | check[1] | check[2]; any; any &= any - 1) {
        const std::uint32_t j = std::uint32_t(__builtin_ctzll(any));
        for (std::uint32_t k = 0; k < 3; ++k) {
            const bool chk = (check[k] >> j) & 1;
            if (!(((sure[k] >> j) & 1) || chk)) continue;
            const std::uint32_t bit = 3 * j + k, w = bit / 64;
            const std::uint64_t below = owned[w] & ((std::uint64_t(1) << (bit % 64)) - 1);
            out.push_back((edge_begin_[b] + before[w] + std::uint32_t(__builtin_popcountll(below))) | (chk ? kCheck : 0));
        }
    }
    return read;
}

#if defined(__x86_64__) && defined(__GNUC__)
namespace {
// FaceBlocks::classify for four blocks a step (AVX2 doubles): the same products, sums, min and
// max in the same order (MINPD(c, a) is std::min(a, c) and MAXPD(c, a) std::max(a, c), NaN
// included), so the same states.
__attribute__((target("avx2"))) void classify_avx2(const float* bounds, std::size_t n, const FacingFilter& f,
                                                   double limit, std::uint8_t* out) {
    const __m256d e[4] = {_mm256_set1_pd(f.ex), _mm256_set1_pd(f.ey), _mm256_set1_pd(f.ez), _mm256_set1_pd(-double(f.w))};
    const __m256d sign = _mm256_set1_pd(-0.0), scale = _mm256_set1_pd(0x1p-20);
    const __m256d bound = _mm256_set1_pd(limit), nbound = _mm256_set1_pd(-limit);
    for (std::size_t b = 0; b < n; b += 4) {
        const float* q = bounds + 8 * b;  // lo[4], hi[4] per block
        __m128 l0 = _mm_loadu_ps(q), l1 = _mm_loadu_ps(q + 8), l2 = _mm_loadu_ps(q + 16), l3 = _mm_loadu_ps(q + 24);
        __m128 h0 = _mm_loadu_ps(q + 4), h1 = _mm_loadu_ps(q + 12), h2 = _mm_loadu_ps(q + 20), h3 = _mm_loadu_ps(q + 28);
        _MM_TRANSPOSE4_PS(l0, l1, l2, l3);  // l_i: component i of the four blocks
        _MM_TRANSPOSE4_PS(h0, h1, h2, h3);
        const __m128 ls[4] = {l0, l1, l2, l3}, hs[4] = {h0, h1, h2, h3};
        __m256d lo = _mm256_setzero_pd(), hi = _mm256_setzero_pd(), mag = _mm256_setzero_pd();
        for (int i = 0; i < 4; ++i) {
            const __m256d a = _mm256_mul_pd(_mm256_cvtps_pd(ls[i]), e[i]), c = _mm256_mul_pd(_mm256_cvtps_pd(hs[i]), e[i]);
            lo = _mm256_add_pd(lo, _mm256_min_pd(c, a));
            hi = _mm256_add_pd(hi, _mm256_max_pd(c, a));
            mag = _mm256_add_pd(mag, _mm256_max_pd(_mm256_andnot_pd(sign, c), _mm256_andnot_pd(sign, a)));
        }
        const __m256d slack = _mm256_mul_pd(mag, scale);
        const __m256d nan = _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(lo, lo, _CMP_UNORD_Q), _mm256_cmp_pd(hi, hi, _CMP_UNORD_Q)),
                                         _mm256_cmp_pd(slack, slack, _CMP_UNORD_Q));
        const unsigned odd = unsigned(_mm256_movemask_pd(nan));
        const unsigned front = unsigned(_mm256_movemask_pd(_mm256_cmp_pd(_mm256_sub_pd(lo, slack), bound, _CMP_GT_OQ))) & ~odd;
        const unsigned back = unsigned(_mm256_movemask_pd(_mm256_cmp_pd(_mm256_add_pd(hi, slack), nbound, _CMP_LT_OQ))) & ~odd;
        for (std::size_t i = 0; i < 4 && b + i < n; ++i)
            out[b + i] = (front >> i) & 1 ? FaceFacing::kFront : (back >> i) & 1 ? FaceFacing::kBack : FaceFacing::kUnknown;
    }
}
}  // namespace
#endif

void FaceBlocks::classify(std::size_t b0, std::size_t b1, const FacingFilter& f, std::uint8_t* out) const {
    classify_within(b0, b1, f, double(f.bound), out);
}

void FaceBlocks::classify_within(std::size_t b0, std::size_t b1, const FacingFilter& f, double limit,
                                 std::uint8_t* out) const {
    std::size_t b = b0;
#if defined(__x86_64__) && defined(__GNUC__)
    static_assert(sizeof(Bounds) == 32);
    if (cpu_has_avx2()) {
        const std::size_t n = (b1 - b0) & ~std::size_t(3);
        classify_avx2(bounds_[b0].lo, n, f, limit, out);
        b += n;
    }
#endif
    for (; b < b1; ++b) {
        double lo, hi;
        distance_range(b, f, lo, hi);
        out[b - b0] = lo > limit ? FaceFacing::kFront : hi < -limit ? FaceFacing::kBack : FaceFacing::kUnknown;  // NaN: unknown
    }
}

void FacingBand::assign(const MeshTopology& mesh, const std::vector<std::uint32_t>& faces) {
    n_ = faces.size();
    ids_ = faces;
    for (auto* row : {&nx_, &ny_, &nz_, &d_}) row->resize(n_);
    for (std::size_t i = 0; i < n_; ++i) {
        const MeshTopology::FacingPlane& p = mesh.facing[faces[i]];
        nx_[i] = p.nx, ny_[i] = p.ny, nz_[i] = p.nz, d_[i] = p.d;
    }
    finish();
}

std::size_t FacingBand::select(const MeshTopology& mesh, const FacingFilter& filter, float limit, const FaceBlocks* blocks,
                               std::uint64_t* front, bool simd) {
    BandRows rows{ids_, nx_, ny_, nz_, d_};
    auto run = [&](std::uint32_t f0, std::uint32_t f1) {
#if defined(__x86_64__) && defined(__GNUC__)
        if (simd && cpu_has_avx2()) return band_rows_avx2(mesh.facing.data(), f0, f1, filter, limit, rows, front);
#endif
        band_rows_scalar(mesh.facing.data(), f0, f1, filter, limit, rows, front);
    };
    const std::uint32_t nf = std::uint32_t(mesh.face_count());
    if (!blocks || !blocks->built_for(mesh)) {
        run(0, nf);
        n_ = rows.n;
        finish();
        return nf;
    }
    // Blocks whose every float distance is beyond +-limit hold no face of the band; runs of the
    // other blocks are streamed as before (so the same faces, in order). A skipped block's faces
    // are all front (every distance above limit) or all back (every one below -limit).
    static_assert(FaceBlocks::kFaces == 64);  // a block's front bits are one word
    // The blocks are classified a chunk at a time (four a step), and the planes of blocks to
    // read are fetched a few blocks ahead (the runs between skipped blocks are short).
    std::size_t read = 0;
    std::uint32_t open = UINT32_MAX;  // first face of the current run of blocks to read
    const std::size_t nb = blocks->size();
    constexpr std::size_t kChunk = 256, kPrefetch = 8;
    std::uint8_t cls[kChunk + kPrefetch];
    std::size_t c0 = 0, c1 = 0;  // cls[i]: the state of block c0 + i, for blocks [c0, c1)
    for (std::size_t b = 0; b <= nb; ++b) {
        bool skip = true;
        if (b < nb) {
            if (b + kPrefetch >= c1 && c1 < nb) {  // the next chunk, keeping the blocks ahead
                const std::size_t keep = c1 - std::min(c1, b);
                std::memmove(cls, cls + (b - c0), keep);
                c0 = b;
                const std::size_t n1 = std::min(nb, c1 + kChunk);
                blocks->classify_within(c1, n1, filter, double(limit), cls + keep);
                c1 = n1;
            }
            const std::size_t a = b + kPrefetch;
            if (a < c1 && cls[a - c0] == FaceFacing::kUnknown) {
                const char* q = reinterpret_cast<const char*>(mesh.facing.data() + a * FaceBlocks::kFaces);
                for (std::size_t i = 0; i < FaceBlocks::kFaces * sizeof(MeshTopology::FacingPlane); i += 64)
                    __builtin_prefetch(q + i);
            }
            const std::uint8_t st = cls[b - c0];
            skip = st != FaceFacing::kUnknown;
            if (skip && front) front[b] = st == FaceFacing::kFront ? ~std::uint64_t(0) : 0;
        }
        const std::uint32_t f = std::uint32_t(std::min<std::size_t>(b * FaceBlocks::kFaces, nf));
        if (!skip && open == UINT32_MAX) open = f;
        if (skip && open != UINT32_MAX) {
            run(open, f);
            read += f - open;
            open = UINT32_MAX;
        }
    }
    n_ = rows.n;
    finish();
    return read;
}

void FacingBand::finish() {
    words_.clear();
    masks_.clear();
    for (std::size_t i = 0; i < n_; ++i) {
        const std::uint32_t f = ids_[i];
        if (words_.empty() || words_.back() != f >> 6) words_.push_back(f >> 6), masks_.push_back(0);
        masks_.back() |= std::uint64_t(1) << (f & 63);
    }
    front_.assign((n_ + 7) / 8 + 16, 0);  // (+16: the word loop reads 16 bytes from any position)
}

void FacingBand::states(const FacingFilter& now, const FacingFilter& before, std::uint64_t* front_bits,
                        std::vector<std::uint32_t>& check, bool simd) {
    const std::size_t n = n_;
    std::uint8_t* front = front_.data();
#if defined(__x86_64__) && defined(__GNUC__)
    if (simd && cpu_has_avx2()) {
        const std::size_t i = band_states_avx2(nx_.data(), ny_.data(), nz_.data(), d_.data(), n, now, before, front, check);
        band_states_scalar(nx_.data(), ny_.data(), nz_.data(), d_.data(), i, n, now, before, front, check);
        if (front_bits) band_words_bmi2(words_.data(), masks_.data(), words_.size(), front, front_bits);
        return;
    }
#endif
    band_states_scalar(nx_.data(), ny_.data(), nz_.data(), d_.data(), 0, n, now, before, front, check);
    if (!front_bits) return;
    std::size_t o = 0;
    for (std::size_t k = 0; k < words_.size(); ++k) {
        std::uint64_t w = front_bits[words_[k]];
        for (std::uint64_t m = masks_[k]; m; m &= m - 1, ++o) {
            const std::uint64_t bit = m & (~m + 1);
            w = (front[o >> 3] >> (o & 7)) & 1 ? (w | bit) : (w & ~bit);
        }
        front_bits[words_[k]] = w;
    }
}

// Faces [lo, hi) of a full view (lo a block start): with blocks, blocks decided as a whole are
// filled with their state (block_state_), runs of the others streamed. Returns the faces whose
// planes were read.
std::size_t FaceFacing::decide(std::size_t lo, std::size_t hi, const FaceBlocks* blocks) {
    const MeshTopology& mesh = *mesh_;
    constexpr std::size_t kPrefetch = 8;  // blocks
    auto run = [&](std::size_t a, std::size_t b) {
#if defined(__x86_64__) && defined(__GNUC__)
        if (cpu_has_avx2()) return facing_states_avx2(mesh.facing.data() + a, b - a, filter_, state_.data() + a);
#endif
        facing_states_scalar(mesh.facing.data() + a, b - a, filter_, state_.data() + a);
    };
    if (!blocks) {
        run(lo, hi);
        return hi - lo;
    }
    constexpr std::size_t kB = FaceBlocks::kFaces;
    std::size_t read = 0, open = SIZE_MAX;
    const std::size_t bend = (hi + kB - 1) / kB;
    blocks->classify(lo / kB, bend, filter_, block_state_.data() + lo / kB);
    for (std::size_t b = lo / kB; b * kB < hi; ++b) {
        // The planes of undecided blocks ahead are fetched now: the runs between decided blocks
        // are short, too short for the hardware to see a stream (a full view after other work
        // finds them in memory).
        if (b + kPrefetch < bend && block_state_[b + kPrefetch] == kUnknown) {
            const char* q = reinterpret_cast<const char*>(mesh.facing.data() + (b + kPrefetch) * kB);
            for (std::size_t i = 0; i < kB * sizeof(MeshTopology::FacingPlane); i += 64) __builtin_prefetch(q + i);
        }
        const std::uint8_t s = block_state_[b];
        const std::size_t f0 = b * kB, f1 = std::min(hi, f0 + kB);
        if (s == kUnknown) {
            if (open == SIZE_MAX) open = f0;
            continue;
        }
        if (open != SIZE_MAX) run(open, f0), read += f0 - open, open = SIZE_MAX;
        std::memset(state_.data() + f0, s, f1 - f0);
    }
    if (open != SIZE_MAX) run(open, hi), read += hi - open;
    return read;
}

void FaceFacing::start_full(const MeshTopology& mesh, const Camera& camera) {
    bind(mesh, camera);
    const std::size_t nf = mesh.face_count();
    state_.resize(nf + kPad);
    std::fill(state_.begin() + std::ptrdiff_t(nf), state_.end(), kSentinel);
    touched_.clear();
    full_ = true;
    block_state_.clear();
    planes_read_ = nf;
}

void FaceFacing::begin_full(const MeshTopology& mesh, const Camera& camera, int threads, const FaceBlocks* blocks) {
    start_full(mesh, camera);
    const std::size_t nf = mesh.face_count();
    if (blocks && !blocks->built_for(mesh)) blocks = nullptr;
    if (blocks) block_state_.resize(blocks->size());
    const std::size_t parts = std::size_t(std::clamp(threads, 1, 64));
    if (parts == 1 || nf < 65536) {
        planes_read_ = decide(0, nf, blocks);
        return;
    }
    std::vector<std::thread> pool;
    std::vector<std::size_t> part_read(parts, 0);
    const std::size_t step = (nf / parts + 63) & ~std::size_t(63);  // cache-line (and block) aligned parts
    for (std::size_t i = 1; i < parts; ++i)
        if (i * step < nf)
            pool.emplace_back([&, i] { part_read[i] = decide(i * step, std::min(nf, (i + 1) * step), blocks); });
    part_read[0] = decide(0, std::min(nf, step), blocks);
    for (auto& t : pool) t.join();
    planes_read_ = 0;
    for (std::size_t r : part_read) planes_read_ += r;
}

void FaceFacing::begin_full_building(const MeshTopology& mesh, const Camera& camera, FaceBlocks& blocks) {
    start_full(mesh, camera);
    const std::size_t nf = mesh.face_count();
    blocks.start(mesh);
    block_state_.resize(blocks.size());
    // Chunks of blocks small enough that their planes, read by the ranges, are still in the
    // cache when the states are decided.
    constexpr std::size_t kChunk = 64;
    planes_read_ = 0;
    for (std::size_t b = 0; b < blocks.size(); b += kChunk) {
        const std::size_t b1 = std::min(blocks.size(), b + kChunk);
        blocks.build_range(b, b1);
        planes_read_ += decide(b * FaceBlocks::kFaces, std::min(nf, b1 * FaceBlocks::kFaces), &blocks);
    }
}

void FaceFacing::carry(const Camera& camera, const std::uint32_t* turned, std::size_t n) {
    bind(*mesh_, camera);
    block_state_.clear();
    planes_read_ = 0;
    std::uint8_t* st = state_.data();
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t s = st[turned[i]];
        st[turned[i]] = s == kUnknown ? kUnknown : std::uint8_t(kFront - s);
    }
}

float FaceFacing::signed_distance(std::uint32_t f) const { return filter_.signed_distance(mesh_->facing[f]); }

std::uint8_t FaceFacing::filter(std::uint32_t f) const { return filter_(mesh_->facing[f]); }

std::uint8_t FaceFacing::resolve(std::uint32_t f) const {
    std::uint8_t s = full_ ? kUnknown : filter(f);
    if (s == kUnknown) {
        const MeshTopology& m = *mesh_;
        const auto& v = m.faces[f];
        if (!shared_) ++exact_;
        s = orient_eye(camera_, m.positions[v[0]], m.positions[v[1]], m.positions[v[2]]) > 0 ? kFront : kBack;
    }
    if (shared_) return s;  // (read by several threads: nothing written)
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
