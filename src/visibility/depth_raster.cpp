#include "visibility/depth_raster.hpp"

#include "visibility/depth_raster_setup.hpp"

namespace inkline {

RasterResult raster_faces_scalar(const RasterJob& job) {
    RasterResult r{job.width, job.height, -1, -1, 0};
    for (std::size_t f = 0; f < job.face_count; ++f) {
        if (job.draw && !job.draw[f]) continue;
        ++r.drawn;
        FaceSetup s;
        if (!setup_face(job, job.faces[f], s)) continue;
        bool wrote = false;
        for (int j = s.j0; j <= s.j1; ++j) {
            const float fj = float(j - s.j0);
            const float ra = s.wa0 + fj * s.da_y, rb = s.wb0 + fj * s.db_y, rq = s.wq0 + fj * s.dq_y;
            float* key = job.key + std::size_t(j) * job.stride;
            std::uint32_t* face = job.face + std::size_t(j) * job.stride;
            for (int i = s.i0; i <= s.i1; ++i) {
                const float fi = float(i - s.i0);
                const float wa = ra + fi * s.da_x, wb = rb + fi * s.db_x, wq = rq + fi * s.dq_x;
                const float k = ((wa * s.ak + wb * s.bk) + wq * s.qk) * s.inv;
                const bool in = (wa >= 0.0f) & (wb >= 0.0f) & (wq >= 0.0f) & (k > key[i]);
                key[i] = in ? k : key[i];
                face[i] = in ? std::uint32_t(f) : face[i];
                wrote |= in;
            }
        }
        if (wrote) {
            r.x0 = std::min(r.x0, s.i0), r.x1 = std::max(r.x1, s.i1);
            r.y0 = std::min(r.y0, s.j0), r.y1 = std::max(r.y1, s.j1);
        }
    }
    return r;
}

#if defined(INKLINE_X86_KERNELS)
RasterResult raster_faces_avx2(const RasterJob& job);  // depth_raster_avx2.cpp
RasterKernel raster_kernel_avx2() { return __builtin_cpu_supports("avx2") ? &raster_faces_avx2 : nullptr; }
#else
RasterKernel raster_kernel_avx2() { return nullptr; }
#endif

RasterKernel raster_kernel() {
    static const RasterKernel chosen = raster_kernel_avx2() ? raster_kernel_avx2() : &raster_faces_scalar;
    return chosen;
}

}  // namespace inkline
