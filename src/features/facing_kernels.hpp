// The facing stage's inner loops, one instruction set a file (Embree's shape): the portable
// kernels (facing_scalar.cpp, the reference), AVX2 + BMI2 (facing_avx2.cpp) and AVX-512 VBMI
// (facing_avx512.cpp), each file built with its own flags on x86-64 (src/CMakeLists.txt). A
// table of them is chosen once, on first use, from what the CPU runs; callers fetch it once per
// pass or block and call whole kernels through it, never one per face or edge. Every vector
// kernel gives exactly the scalar kernel's result (tests/test_facing_kernels.cpp).
//
// The vector files see only this header's types: no std::vector or other template whose
// out-of-line code, compiled there with wider instructions, could be the copy the linker keeps
// for the portable code too. Growing the outputs is the callers' job (facing.cpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "features/facing.hpp"

namespace inkline {

// The rows FacingBand::select writes: n faces so far, and room after them for the faces of the
// call plus 8 (a vector kernel stores a group of 8 whole, its selected faces first).
struct BandRowsOut {
    std::uint32_t* ids;
    float *nx, *ny, *nz, *d;
    std::size_t n;
};

struct FacingKernels {
    const char* name;  // "scalar", "avx2", "avx512"
    // FaceFacing's filter for faces [0, n): kFront, kBack, or kUnknown (also NaN planes).
    void (*facing_states)(const MeshTopology::FacingPlane* planes, std::size_t n, const FacingFilter& filter,
                          std::uint8_t* out);
    // FaceBlocks' plane ranges of blocks [b0, b1) of kFaces faces (nf faces in all): per block
    // lo[4] then hi[4] (nx, ny, nz, d) into bounds (block b0's first), lo[0] = hi[0] = NaN where
    // the block holds a NaN plane or no face. Ranges are exact up to the sign of zero.
    void (*block_ranges)(const MeshTopology::FacingPlane* planes, std::size_t nf, std::size_t b0, std::size_t b1,
                         float* bounds);
    // FaceBlocks::classify_within for n blocks whose ranges start at bounds.
    void (*classify_blocks)(const float* bounds, std::size_t n, const FacingFilter& filter, double limit,
                            std::uint8_t* out);
    // FacingBand::select's pass over faces [f0, f1) (f0 a multiple of 64): the faces whose float
    // distance is not above limit (NaN planes included) appended to rows; with front, the bit of
    // each face set where its float distance is above zero, cleared elsewhere.
    void (*band_rows)(const MeshTopology::FacingPlane* planes, std::uint32_t f0, std::uint32_t f1,
                      const FacingFilter& filter, float limit, BandRowsOut& rows, std::uint64_t* front);
    // FacingBand::states over the band's n rows: front bits (8 faces a byte) as `now` decides,
    // and the positions where the filters disagree or `now` cannot decide written to check (room
    // for n); returns how many.
    std::size_t (*band_states)(const float* nx, const float* ny, const float* nz, const float* d, std::size_t n,
                               const FacingFilter& now, const FacingFilter& before, std::uint8_t* front,
                               std::uint32_t* check);
    // The band's front bits (in band order) scattered into the words of a per-face bit set.
    void (*band_words)(const std::uint32_t* words, const std::uint64_t* masks, std::size_t nw, const std::uint8_t* front,
                       std::uint64_t* bits);
    // BlockEdges: candidate bits of n escapes (16 a word; bits zeroed by the caller).
    void (*escape_bits)(const std::uint8_t* states, const std::uint32_t* self, const std::uint32_t* far, std::size_t n,
                        std::uint16_t* bits);
    // BlockEdges: one block's corner masks (corner-major, bit j of word k): the neighbour's state
    // differs from the face's, both decided (sure), or the neighbour undecided (check); undecided
    // faces. Returns false (all masks zero) where both windows hold one decided state.
    bool (*block_masks)(const std::uint8_t* states, std::uint32_t base, std::uint32_t base2, const std::uint8_t* index,
                        std::uint64_t sure[3], std::uint64_t check[3], std::uint64_t& undecided);
    // BlockEdges: the edge ids of one block's marked corners (owned corners only, in edge order,
    // BlockEdges::kCheck on those of `check`) written to out (room for 192); returns how many.
    std::uint32_t (*block_edges)(const std::uint64_t sure[3], const std::uint64_t check[3], const std::uint64_t owned[3],
                                 std::uint32_t e0, std::uint32_t* out);
    // The exhaustive scan's candidates among edges [e0, e1): edges whose two face states differ
    // or whose first face is undecided (the second face clamped to nf: the sentinel). Written to
    // cand (room for e1 - e0); returns how many.
    std::uint32_t (*edge_candidates)(const std::array<std::uint32_t, 2>* edge_face, const std::uint8_t* states,
                                     std::uint32_t nf, std::uint32_t e0, std::uint32_t e1, std::uint32_t* cand);
};

enum class FacingIsa { Scalar, Avx2, Avx512 };

// facing_kernels() (facing.hpp) is AVX-512 VBMI where the CPU runs it, else AVX2 + BMI2, else
// scalar. The kernels of one instruction set, or null where this build or this CPU lacks it (tests).
const FacingKernels* facing_kernels_for(FacingIsa isa);

// The portable kernels (facing_scalar.cpp); the vector files finish their tails with them.
namespace scalar_kernels {
void facing_states(const MeshTopology::FacingPlane* planes, std::size_t n, const FacingFilter& filter, std::uint8_t* out);
void block_ranges(const MeshTopology::FacingPlane* planes, std::size_t nf, std::size_t b0, std::size_t b1, float* bounds);
void classify_blocks(const float* bounds, std::size_t n, const FacingFilter& filter, double limit, std::uint8_t* out);
void band_rows(const MeshTopology::FacingPlane* planes, std::uint32_t f0, std::uint32_t f1, const FacingFilter& filter,
               float limit, BandRowsOut& rows, std::uint64_t* front);
std::size_t band_states(const float* nx, const float* ny, const float* nz, const float* d, std::size_t n,
                        const FacingFilter& now, const FacingFilter& before, std::uint8_t* front, std::uint32_t* check);
std::size_t band_states_from(const float* nx, const float* ny, const float* nz, const float* d, std::size_t i0,
                             std::size_t n, const FacingFilter& now, const FacingFilter& before, std::uint8_t* front,
                             std::uint32_t* check);
void band_words(const std::uint32_t* words, const std::uint64_t* masks, std::size_t nw, const std::uint8_t* front,
                std::uint64_t* bits);
void escape_bits(const std::uint8_t* states, const std::uint32_t* self, const std::uint32_t* far, std::size_t n,
                 std::uint16_t* bits);
bool block_masks(const std::uint8_t* states, std::uint32_t base, std::uint32_t base2, const std::uint8_t* index,
                 std::uint64_t sure[3], std::uint64_t check[3], std::uint64_t& undecided);
std::uint32_t block_edges(const std::uint64_t sure[3], const std::uint64_t check[3], const std::uint64_t owned[3],
                          std::uint32_t e0, std::uint32_t* out);
std::uint32_t edge_candidates(const std::array<std::uint32_t, 2>* edge_face, const std::uint8_t* states, std::uint32_t nf,
                              std::uint32_t e0, std::uint32_t e1, std::uint32_t* cand);
}  // namespace scalar_kernels

// The vector kernels (x86-64 builds only), each the same function as its scalar namesake.
namespace avx2_kernels {
extern const FacingKernels table;
void facing_states(const MeshTopology::FacingPlane* planes, std::size_t n, const FacingFilter& filter, std::uint8_t* out);
void block_ranges(const MeshTopology::FacingPlane* planes, std::size_t nf, std::size_t b0, std::size_t b1, float* bounds);
void classify_blocks(const float* bounds, std::size_t n, const FacingFilter& filter, double limit, std::uint8_t* out);
void band_rows(const MeshTopology::FacingPlane* planes, std::uint32_t f0, std::uint32_t f1, const FacingFilter& filter,
               float limit, BandRowsOut& rows, std::uint64_t* front);
std::size_t band_states(const float* nx, const float* ny, const float* nz, const float* d, std::size_t n,
                        const FacingFilter& now, const FacingFilter& before, std::uint8_t* front, std::uint32_t* check);
void band_words(const std::uint32_t* words, const std::uint64_t* masks, std::size_t nw, const std::uint8_t* front,
                std::uint64_t* bits);
bool block_masks(const std::uint8_t* states, std::uint32_t base, std::uint32_t base2, const std::uint8_t* index,
                 std::uint64_t sure[3], std::uint64_t check[3], std::uint64_t& undecided);
std::uint32_t block_edges(const std::uint64_t sure[3], const std::uint64_t check[3], const std::uint64_t owned[3],
                          std::uint32_t e0, std::uint32_t* out);
std::uint32_t edge_candidates(const std::array<std::uint32_t, 2>* edge_face, const std::uint8_t* states, std::uint32_t nf,
                              std::uint32_t e0, std::uint32_t e1, std::uint32_t* cand);
}  // namespace avx2_kernels
// AVX-512 VBMI (with AVX2 + BMI2 for the rest): the escapes and the block masks.
namespace avx512_kernels {
extern const FacingKernels table;
}  // namespace avx512_kernels

}  // namespace inkline
