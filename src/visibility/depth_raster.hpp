// The depth buffer's fill (depth_buffer.hpp), one instruction set a file as features/facing_kernels.hpp
// does it: the portable kernel (depth_raster.cpp, the reference) and AVX2 (depth_raster_avx2.cpp,
// built with -mavx2 on x86-64), chosen once from what the CPU runs. Both evaluate the same float
// expressions in the same order with no fused multiply-add, so they write the same buffer bit for
// bit (tests/test_fast_visibility.cpp). Only plain pointers cross into the vector file (no
// templates whose out-of-line copies, built with wider instructions, the linker could keep for
// portable code).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace inkline {

struct RasterJob {
    const float *vx, *vy, *vk;                  // per mesh vertex: buffer position and key
    const std::array<std::uint32_t, 3>* faces;  // the mesh's faces
    std::size_t face_count;
    const std::uint8_t* draw;  // per face: draw it (null: all)
    float* key;                // the buffer, row-major, `stride` a multiple of 8 and >= width
    std::uint32_t* face;
    int stride, width, height;
};

struct RasterResult {
    int x0, y0, x1, y1;  // pixels written lie in [x0, x1] x [y0, y1] (x1 < x0: none)
    std::size_t drawn;   // faces to draw
};

using RasterKernel = RasterResult (*)(const RasterJob&);

RasterResult raster_faces_scalar(const RasterJob& job);
// The AVX2 kernel where this build has one and the CPU runs it, else null.
RasterKernel raster_kernel_avx2();
// The kernel to use: AVX2 where available, else the scalar one.
RasterKernel raster_kernel();

}  // namespace inkline
