// BlockEdges' kernels with AVX-512 VBMI (facing_kernels.hpp): byte permutations over the two
// windows of 128 states, and gathers for the escapes. Built with -mavx512f -mavx512bw
// -mavx512vbmi -mbmi2; integer work only (-mavx512f also enables FMA, which a float distance
// here would then differ by). The table's other kernels are the AVX2 ones.
#include <immintrin.h>

#include "features/facing_kernels.hpp"

namespace inkline::avx512_kernels {
namespace {

// Sixteen escapes a step: both states gathered (as 32-bit words, masked to their low byte).
void escape_bits(const std::uint8_t* st, const std::uint32_t* self, const std::uint32_t* far, std::size_t n,
                 std::uint16_t* bits) {
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

// Both windows as two 128-byte tables, each index's neighbour state fetched by one two-table
// byte permutation per window and a blend on the index's top bit.
bool block_masks(const std::uint8_t* st, std::uint32_t base, std::uint32_t base2, const std::uint8_t* index,
                 std::uint64_t sure[3], std::uint64_t check[3], std::uint64_t& undecided) {
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

}  // namespace

constinit const FacingKernels table{"avx512",
                                    avx2_kernels::facing_states,
                                    avx2_kernels::block_ranges,
                                    avx2_kernels::classify_blocks,
                                    avx2_kernels::band_rows,
                                    avx2_kernels::band_states,
                                    avx2_kernels::band_words,
                                    escape_bits,
                                    block_masks,
                                    avx2_kernels::block_edges,
                                    avx2_kernels::edge_candidates};

}  // namespace inkline::avx512_kernels
