// The portable facing kernels: the reference every vector kernel must equal (facing_kernels.hpp),
// and the table of kernels chosen once for this CPU.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "features/facing_kernels.hpp"

namespace inkline {

namespace scalar_kernels {

void facing_states(const MeshTopology::FacingPlane* __restrict p, std::size_t nf, const FacingFilter& flt,
                   std::uint8_t* __restrict out) {
    const float ex = flt.ex, ey = flt.ey, ez = flt.ez, w = flt.w, b = flt.bound;
    for (std::size_t f = 0; f < nf; ++f) {
        const float det = p[f].nx * ex + p[f].ny * ey + p[f].nz * ez - w * p[f].d;
        out[f] = std::uint8_t(std::uint8_t(det > b) + std::uint8_t(!(det < -b)));
    }
}

void block_ranges(const MeshTopology::FacingPlane* planes, std::size_t nf, std::size_t b0, std::size_t b1,
                  float* bounds) {
    constexpr std::size_t kFaces = FaceBlocks::kFaces;
    for (std::size_t b = b0; b < b1; ++b) {
        float* lo = bounds + 8 * (b - b0);
        float* hi = lo + 4;
        const std::size_t f0 = b * kFaces, f1 = std::min(nf, f0 + kFaces);
        for (int i = 0; i < 4; ++i) lo[i] = INFINITY, hi[i] = -INFINITY;
        bool nan = false;
        for (std::size_t f = f0; f < f1; ++f) {
            const auto& p = planes[f];
            const float v[4] = {p.nx, p.ny, p.nz, p.d};
            for (int i = 0; i < 4; ++i) {
                nan = nan || std::isnan(v[i]);
                lo[i] = std::min(lo[i], v[i]);
                hi[i] = std::max(hi[i], v[i]);
            }
        }
        if (nan || f0 == f1) lo[0] = hi[0] = NAN;  // never decided as a whole
    }
}

// The filter's float distance is fl(fl(fl(nx ex) + fl(ny ey)) + fl(nz ez)) - fl(w d); its real
// value over a block lies in the interval sum of the four products' ranges (computed in double:
// the products of two floats are exact, the sums err by 2^-52 relative), and the float
// evaluation errs from it by at most 4 * 2^-24 * (|nx ex| + |ny ey| + |nz ez| + |w d|); the range
// is widened by 2^-20 times that sum's bound. (FaceBlocks::distance_range.)
void classify_blocks(const float* bounds, std::size_t n, const FacingFilter& f, double limit, std::uint8_t* out) {
    for (std::size_t b = 0; b < n; ++b) {
        double lo, hi;
        FaceBlocks::distance_range(bounds + 8 * b, f, lo, hi);
        out[b] = lo > limit ? FaceFacing::kFront : hi < -limit ? FaceFacing::kBack : FaceFacing::kUnknown;  // NaN: unknown
    }
}

void band_rows(const MeshTopology::FacingPlane* p, std::uint32_t f0, std::uint32_t f1, const FacingFilter& flt,
               float limit, BandRowsOut& rows, std::uint64_t* front) {
    for (std::uint32_t f = f0; f < f1; ++f) {
        const float det = flt.signed_distance(p[f]);
        if (!(std::abs(det) > limit)) {
            const std::size_t i = rows.n++;
            rows.ids[i] = f, rows.nx[i] = p[f].nx, rows.ny[i] = p[f].ny, rows.nz[i] = p[f].nz, rows.d[i] = p[f].d;
        }
        if (front) {
            const std::uint64_t m = std::uint64_t(1) << (f & 63);
            front[f >> 6] = det > 0.0f ? (front[f >> 6] | m) : (front[f >> 6] & ~m);
        }
    }
}

std::size_t band_states_from(const float* nx, const float* ny, const float* nz, const float* d, std::size_t i0,
                             std::size_t n, const FacingFilter& now, const FacingFilter& before, std::uint8_t* front,
                             std::uint32_t* check) {
    std::size_t k = 0;
    for (std::size_t i = i0; i < n; ++i) {
        const MeshTopology::FacingPlane p{nx[i], ny[i], nz[i], d[i]};
        const std::uint8_t a = now(p), b = before(p);
        const std::uint8_t m = std::uint8_t(1u << (i & 7));
        front[i >> 3] = a == FaceFacing::kFront ? std::uint8_t(front[i >> 3] | m) : std::uint8_t(front[i >> 3] & ~m);
        check[k] = std::uint32_t(i);
        k += a != b || a == FaceFacing::kUnknown;
    }
    return k;
}

std::size_t band_states(const float* nx, const float* ny, const float* nz, const float* d, std::size_t n,
                        const FacingFilter& now, const FacingFilter& before, std::uint8_t* front, std::uint32_t* check) {
    return band_states_from(nx, ny, nz, d, 0, n, now, before, front, check);
}

void band_words(const std::uint32_t* words, const std::uint64_t* masks, std::size_t nw, const std::uint8_t* front,
                std::uint64_t* bits) {
    std::size_t o = 0;  // band position of the word's first face
    for (std::size_t k = 0; k < nw; ++k) {
        std::uint64_t w = bits[words[k]];
        for (std::uint64_t m = masks[k]; m; m &= m - 1, ++o) {
            const std::uint64_t bit = m & (~m + 1);
            w = (front[o >> 3] >> (o & 7)) & 1 ? (w | bit) : (w & ~bit);
        }
        bits[words[k]] = w;
    }
}

void escape_bits(const std::uint8_t* st, const std::uint32_t* self, const std::uint32_t* far, std::size_t n,
                 std::uint16_t* bits) {
    for (std::size_t i = 0; i < n; ++i) {
        // A candidate where its face is decided and differs from its neighbour (an undecided face
        // makes all its edges candidates anyway, BlockEdges::scan_block).
        const std::uint8_t a = st[self[i]], c = st[far[i]];
        bits[i / 16] |= std::uint16_t(std::uint16_t(a != c && !(a & FaceFacing::kUnknown)) << (i % 16));
    }
}

bool block_masks(const std::uint8_t* st, std::uint32_t base, std::uint32_t base2, const std::uint8_t* index,
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

std::uint32_t block_edges(const std::uint64_t sure[3], const std::uint64_t check[3], const std::uint64_t owned[3],
                          std::uint32_t e0, std::uint32_t* out) {
    const std::uint32_t before[3] = {0, std::uint32_t(__builtin_popcountll(owned[0])),
                                     std::uint32_t(__builtin_popcountll(owned[0]) + __builtin_popcountll(owned[1]))};
    std::uint32_t n = 0;
    for (std::uint64_t any = sure[0] | sure[1] | sure[2] | check[0] | check[1] | check[2]; any; any &= any - 1) {
        const std::uint32_t j = std::uint32_t(__builtin_ctzll(any));
        for (std::uint32_t k = 0; k < 3; ++k) {
            const bool chk = (check[k] >> j) & 1;
            if (!(((sure[k] >> j) & 1) || chk)) continue;
            const std::uint32_t bit = 3 * j + k, w = bit / 64;
            const std::uint64_t below = owned[w] & ((std::uint64_t(1) << (bit % 64)) - 1);
            out[n++] = (e0 + before[w] + std::uint32_t(__builtin_popcountll(below))) | (chk ? BlockEdges::kCheck : 0);
        }
    }
    return n;
}

std::uint32_t edge_candidates(const std::array<std::uint32_t, 2>* __restrict ef, const std::uint8_t* __restrict st,
                              std::uint32_t nf, std::uint32_t e0, std::uint32_t e1, std::uint32_t* __restrict cand) {
    std::uint32_t n = 0;
    for (std::uint32_t e = e0; e < e1; ++e) {
        const std::uint8_t a = st[ef[e][0]], b = st[std::min(ef[e][1], nf)];
        cand[n] = e;
        n += ((a ^ b) | (a & FaceFacing::kUnknown)) != 0;
    }
    return n;
}

constinit const FacingKernels table{"scalar",     facing_states, block_ranges, classify_blocks, band_rows,
                              band_states,  band_words,    escape_bits,  block_masks,     block_edges,
                              edge_candidates};

}  // namespace scalar_kernels

namespace {
bool cpu_runs(FacingIsa isa) {
#if defined(INKLINE_X86_KERNELS)
    const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi2");
    if (isa == FacingIsa::Avx2) return avx2;
    if (isa == FacingIsa::Avx512)
        return avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
               __builtin_cpu_supports("avx512vbmi");
#endif
    return isa == FacingIsa::Scalar;
}
}  // namespace

const FacingKernels* facing_kernels_for(FacingIsa isa) {
    if (!cpu_runs(isa)) return nullptr;
#if defined(INKLINE_X86_KERNELS)
    if (isa == FacingIsa::Avx512) return &avx512_kernels::table;
    if (isa == FacingIsa::Avx2) return &avx2_kernels::table;
#endif
    return &scalar_kernels::table;
}

const FacingKernels& facing_kernels(bool vector) {
    static const FacingKernels& chosen = []() -> const FacingKernels& {
        for (FacingIsa isa : {FacingIsa::Avx512, FacingIsa::Avx2})
            if (const FacingKernels* k = facing_kernels_for(isa)) return *k;
        return scalar_kernels::table;
    }();
    return vector ? chosen : scalar_kernels::table;
}

}  // namespace inkline
