// The facing kernels with AVX2 + BMI2 (facing_kernels.hpp), built with -mavx2 -mbmi2 and no FMA:
// every distance is the same products and sums in the same order as the scalar kernel's (an FMA
// would round once where it rounds twice), so the same floats and the same states. Tails shorter
// than a vector step go to the scalar kernels.
#include <immintrin.h>

#include <cmath>
#include <cstring>

#include "features/facing_kernels.hpp"

namespace inkline::avx2_kernels {
namespace {

// Eight consecutive planes (nx, ny, nz, d) transposed to four rows of eight lanes.
struct Planes8 {
    __m256 nx, ny, nz, d;
};
inline void load_planes8(const float* q, Planes8& out) {
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
inline void load_eye8(const FacingFilter& f, Eye8& out) {
    out.ex = _mm256_set1_ps(f.ex);
    out.ey = _mm256_set1_ps(f.ey);
    out.ez = _mm256_set1_ps(f.ez);
    out.w = _mm256_set1_ps(f.w);
}
// The filter's distance of the eye to eight planes: the same products and sums in the same order
// as FacingFilter::signed_distance, so the same floats.
inline void eye_distance8(const Planes8& p, const Eye8& e, __m256& out) {
    out = _mm256_sub_ps(
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(p.nx, e.ex), _mm256_mul_ps(p.ny, e.ey)), _mm256_mul_ps(p.nz, e.ez)),
        _mm256_mul_ps(e.w, p.d));
}

}  // namespace

// 8 faces a step: the two comparisons as bit masks, spread to one byte per face with pdep.
void facing_states(const MeshTopology::FacingPlane* __restrict p, std::size_t nf, const FacingFilter& flt,
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
    scalar_kernels::facing_states(p + f, nf - f, flt, out + f);
}

// Four faces a step into four accumulators (min and max are exact, so any order gives the same
// ranges, up to the sign of zero; a NaN plane marks the block, whatever the ranges say): the
// chains of dependent min/max no longer bound the speed.
void block_ranges(const MeshTopology::FacingPlane* planes, std::size_t nf, std::size_t b0, std::size_t b1,
                  float* bounds) {
    constexpr std::size_t kFaces = FaceBlocks::kFaces;
    for (std::size_t b = b0; b < b1; ++b) {
        float* r = bounds + 8 * (b - b0);
        const std::size_t f0 = b * kFaces, f1 = nf < f0 + kFaces ? nf : f0 + kFaces;
        __m128 lo = _mm_set1_ps(INFINITY), hi = _mm_set1_ps(-INFINITY), un = _mm_setzero_ps();
        __m128 lo1 = lo, lo2 = lo, lo3 = lo, hi1 = hi, hi2 = hi, hi3 = hi;
        std::size_t f = f0;
        for (; f + 4 <= f1; f += 4) {
            const float* q = &planes[f].nx;  // FacingPlane is 16-byte aligned
            const __m128 p0 = _mm_load_ps(q), p1 = _mm_load_ps(q + 4), p2 = _mm_load_ps(q + 8), p3 = _mm_load_ps(q + 12);
            lo = _mm_min_ps(lo, p0), lo1 = _mm_min_ps(lo1, p1), lo2 = _mm_min_ps(lo2, p2), lo3 = _mm_min_ps(lo3, p3);
            hi = _mm_max_ps(hi, p0), hi1 = _mm_max_ps(hi1, p1), hi2 = _mm_max_ps(hi2, p2), hi3 = _mm_max_ps(hi3, p3);
            un = _mm_or_ps(un, _mm_or_ps(_mm_cmpunord_ps(p0, p1), _mm_cmpunord_ps(p2, p3)));
        }
        for (; f < f1; ++f) {
            const __m128 p = _mm_load_ps(&planes[f].nx);
            lo = _mm_min_ps(lo, p);
            hi = _mm_max_ps(hi, p);
            un = _mm_or_ps(un, _mm_cmpunord_ps(p, p));
        }
        lo = _mm_min_ps(_mm_min_ps(lo, lo1), _mm_min_ps(lo2, lo3));
        hi = _mm_max_ps(_mm_max_ps(hi, hi1), _mm_max_ps(hi2, hi3));
        _mm_storeu_ps(r, lo);
        _mm_storeu_ps(r + 4, hi);
        if (_mm_movemask_ps(un) != 0 || f0 == f1) r[0] = r[4] = NAN;  // never decided as a whole
    }
}

// Four blocks a step in doubles: the same products, sums, min and max in the same order as the
// scalar kernel (MINPD(c, a) is std::min(a, c) and MAXPD(c, a) std::max(a, c), NaN included),
// so the same states.
void classify_blocks(const float* bounds, std::size_t n, const FacingFilter& f, double limit, std::uint8_t* out) {
    const __m256d e[4] = {_mm256_set1_pd(f.ex), _mm256_set1_pd(f.ey), _mm256_set1_pd(f.ez), _mm256_set1_pd(-double(f.w))};
    const __m256d sign = _mm256_set1_pd(-0.0), scale = _mm256_set1_pd(0x1p-20);
    const __m256d bound = _mm256_set1_pd(limit), nbound = _mm256_set1_pd(-limit);
    const std::size_t n4 = n & ~std::size_t(3);
    for (std::size_t b = 0; b < n4; b += 4) {
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
        for (std::size_t i = 0; i < 4; ++i)
            out[b + i] = (front >> i) & 1 ? FaceFacing::kFront : (back >> i) & 1 ? FaceFacing::kBack : FaceFacing::kUnknown;
    }
    scalar_kernels::classify_blocks(bounds + 8 * n4, n - n4, f, limit, out + n4);
}

namespace {
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
}  // namespace

// Eight faces a step: the selected lanes of the transposed planes (the rows' own layout) and of
// the ids packed to the front and stored whole.
void band_rows(const MeshTopology::FacingPlane* p, std::uint32_t f0, std::uint32_t nf, const FacingFilter& flt,
               float limit, BandRowsOut& rows, std::uint64_t* front) {
    Eye8 eye;
    load_eye8(flt, eye);
    const __m256 lim = _mm256_set1_ps(limit), zero = _mm256_setzero_ps();
    const __m256 abs_mask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    std::uint32_t f = f0;
    std::uint64_t word = 0;  // front bits of the current 64 faces
    std::size_t n = rows.n;
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
        const __m256i idx = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPack.lanes[m]));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(rows.ids + n),
                            _mm256_permutevar8x32_epi32(_mm256_add_epi32(_mm256_set1_epi32(int(f)), lane), idx));
        _mm256_storeu_ps(rows.nx + n, _mm256_permutevar8x32_ps(p8.nx, idx));
        _mm256_storeu_ps(rows.ny + n, _mm256_permutevar8x32_ps(p8.ny, idx));
        _mm256_storeu_ps(rows.nz + n, _mm256_permutevar8x32_ps(p8.nz, idx));
        _mm256_storeu_ps(rows.d + n, _mm256_permutevar8x32_ps(p8.d, idx));
        n += unsigned(__builtin_popcount(m));
    }
    rows.n = n;
    if (front && (f & 63)) {  // a word begun: its first faces from here, the rest by the scalar loop
        const std::uint64_t keep = (std::uint64_t(1) << (f & 63)) - 1;
        front[f >> 6] = (front[f >> 6] & ~keep) | word;
    }
    scalar_kernels::band_rows(p, f, nf, flt, limit, rows, front);
}

// 8 faces a step from the four rows.
std::size_t band_states(const float* nx, const float* ny, const float* nz, const float* d, std::size_t n,
                        const FacingFilter& now, const FacingFilter& before, std::uint8_t* front, std::uint32_t* check) {
    Eye8 eye_now, eye_before;
    load_eye8(now, eye_now);
    load_eye8(before, eye_before);
    const __m256 ab = _mm256_set1_ps(now.bound), anb = _mm256_set1_ps(-now.bound);
    const __m256 bb = _mm256_set1_ps(before.bound), bnb = _mm256_set1_ps(-before.bound);
    std::size_t i = 0, k = 0;
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
            check[k++] = std::uint32_t(i + unsigned(__builtin_ctz(odd)));
            odd &= odd - 1;
        }
    }
    return k + scalar_kernels::band_states_from(nx, ny, nz, d, i, n, now, before, front, check + k);
}

// The band's front bits scattered into the words of the face bit set (pdep per word).
void band_words(const std::uint32_t* words, const std::uint64_t* masks, std::size_t nw, const std::uint8_t* front,
                std::uint64_t* bits) {
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

namespace {
// Bit `shift` of each byte's state (7: bit 0, 6: bit 1) moved to its top bit, one bit per byte.
inline std::uint32_t state_bits(__m256i v, int shift) {
    return std::uint32_t(_mm256_movemask_epi8(_mm256_slli_epi16(v, shift)));
}
}  // namespace
// AVX2 has no byte permutation across 128 or 256 entries: the two windows' 256 states as two
// 256-bit planes (their bit 0 and bit 1, one bit per face), and each index's bits looked up in
// them (its byte by two in-lane shuffles, its bit by a mask): the same states, so the same masks.
bool block_masks(const std::uint8_t* st, std::uint32_t base, std::uint32_t base2, const std::uint8_t* index,
                 std::uint64_t sure[3], std::uint64_t check[3], std::uint64_t& undecided) {
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

namespace {
// The corner-major masks (bit j of word k) interleaved to corner order (bit 3 j + k of three
// words), then compressed to the owned corners (pext): bit r of word w is the edge numbered
// r-th in that word's corners.
inline void corner_order(const std::uint64_t m[3], std::uint64_t out[3]) {
    constexpr std::uint64_t k0 = 0x9249249249249249ull, k1 = k0 << 1, k2 = k0 << 2;  // bits = 0, 1, 2 mod 3
    out[0] = _pdep_u64(m[0], k0) | _pdep_u64(m[1], k1) | _pdep_u64(m[2], k2);
    out[1] = _pdep_u64(m[0] >> 22, k2) | _pdep_u64(m[1] >> 21, k0) | _pdep_u64(m[2] >> 21, k1);  // bit 64: j 21, k 1
    out[2] = _pdep_u64(m[0] >> 43, k1) | _pdep_u64(m[1] >> 43, k2) | _pdep_u64(m[2] >> 42, k0);  // bit 128: j 42, k 2
}
}  // namespace
static_assert(BlockEdges::kCheck == 1u << 31);
std::uint32_t block_edges(const std::uint64_t sure[3], const std::uint64_t check[3], const std::uint64_t owned[3],
                          std::uint32_t e0, std::uint32_t* out) {
    std::uint64_t all[3], chk[3];
    const std::uint64_t any[3] = {sure[0] | check[0], sure[1] | check[1], sure[2] | check[2]};
    corner_order(any, all);
    corner_order(check, chk);
    std::uint32_t n = 0;
    for (int w = 0; w < 3; ++w) {
        for (std::uint64_t r = _pext_u64(all[w], owned[w]), c = _pext_u64(chk[w], owned[w]); r; r &= r - 1) {
            const unsigned i = unsigned(__builtin_ctzll(r));
            out[n++] = (e0 + i) | (std::uint32_t((c >> i) & 1) << 31);  // (BlockEdges::kCheck)
        }
        e0 += std::uint32_t(__builtin_popcountll(owned[w]));
    }
    return n;
}

// 8 edges a step: the face pairs deinterleaved, the two states gathered as 32-bit words
// (FaceFacing::states() is padded for that) and masked to their low byte; candidates are rare,
// so they are written from the comparison's bit mask.
std::uint32_t edge_candidates(const std::array<std::uint32_t, 2>* __restrict ef, const std::uint8_t* __restrict st,
                              std::uint32_t nf, std::uint32_t e0, std::uint32_t e1, std::uint32_t* __restrict cand) {
    const __m256i last = _mm256_set1_epi32(int(nf)), low = _mm256_set1_epi32(0xff);
    const __m256i unknown = _mm256_set1_epi32(FaceFacing::kUnknown), zero = _mm256_setzero_si256();
    const int* states = reinterpret_cast<const int*>(st);
    std::uint32_t n = 0, e = e0;
    for (; e + 8 <= e1; e += 8) {
        const __m256 lo = _mm256_loadu_ps(reinterpret_cast<const float*>(&ef[e][0]));
        const __m256 hi = _mm256_loadu_ps(reinterpret_cast<const float*>(&ef[e + 4][0]));
        // shuffle gives edges 0 1 4 5 | 2 3 6 7; the 64-bit permute puts them in order.
        const __m256i f0 = _mm256_permute4x64_epi64(_mm256_castps_si256(_mm256_shuffle_ps(lo, hi, 0x88)), 0xD8);
        const __m256i f1 = _mm256_min_epu32(
            _mm256_permute4x64_epi64(_mm256_castps_si256(_mm256_shuffle_ps(lo, hi, 0xDD)), 0xD8), last);
        const __m256i a = _mm256_and_si256(_mm256_i32gather_epi32(states, f0, 1), low);
        const __m256i b = _mm256_and_si256(_mm256_i32gather_epi32(states, f1, 1), low);
        const __m256i x = _mm256_or_si256(_mm256_xor_si256(a, b), _mm256_and_si256(a, unknown));
        unsigned mask = ~unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(x, zero)))) & 0xffu;
        while (mask) {
            cand[n++] = e + unsigned(__builtin_ctz(mask));
            mask &= mask - 1;
        }
    }
    return n + scalar_kernels::edge_candidates(ef, st, nf, e, e1, cand + n);
}

// (escape_bits: only the AVX-512 table has a vector kernel for it.)
constinit const FacingKernels table{"avx2",      facing_states, block_ranges, classify_blocks,
                          band_rows,   band_states,   band_words,   scalar_kernels::escape_bits,
                          block_masks, block_edges,   edge_candidates};

}  // namespace inkline::avx2_kernels
