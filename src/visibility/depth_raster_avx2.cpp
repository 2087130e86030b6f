// The depth buffer's AVX2 kernel (depth_raster.hpp): 8 pixels of a row at a time, in chunks
// aligned to 8 (the buffer's stride is a multiple of 8), lanes outside the face's box masked.
#include <immintrin.h>

#include "visibility/depth_raster.hpp"
#include "visibility/depth_raster_setup.hpp"

namespace inkline {

RasterResult raster_faces_avx2(const RasterJob& job) {
    RasterResult r{job.width, job.height, -1, -1, 0};
    const __m256 zero = _mm256_setzero_ps();
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    for (std::size_t f = 0; f < job.face_count; ++f) {
        if (job.draw && !job.draw[f]) continue;
        ++r.drawn;
        FaceSetup s;
        if (!setup_face(job, job.faces[f], s)) continue;
        const __m256 dax = _mm256_set1_ps(s.da_x), dbx = _mm256_set1_ps(s.db_x), dqx = _mm256_set1_ps(s.dq_x);
        const __m256 ak = _mm256_set1_ps(s.ak), bk = _mm256_set1_ps(s.bk), qk = _mm256_set1_ps(s.qk);
        const __m256 inv = _mm256_set1_ps(s.inv), span = _mm256_set1_ps(float(s.i1 - s.i0));
        const __m256i id = _mm256_set1_epi32(int(f));
        const int x_begin = s.i0 & ~7;
        int wrote = 0;
        for (int j = s.j0; j <= s.j1; ++j) {
            const float fj = float(j - s.j0);
            const __m256 ra = _mm256_set1_ps(s.wa0 + fj * s.da_y), rb = _mm256_set1_ps(s.wb0 + fj * s.db_y),
                         rq = _mm256_set1_ps(s.wq0 + fj * s.dq_y);
            float* key = job.key + std::size_t(j) * job.stride;
            std::uint32_t* face = job.face + std::size_t(j) * job.stride;
            for (int x = x_begin; x <= s.i1; x += 8) {
                // float(i - i0) per lane: exact for the buffer's sizes, as the scalar kernel's.
                const __m256 fi = _mm256_cvtepi32_ps(_mm256_add_epi32(lane, _mm256_set1_epi32(x - s.i0)));
                const __m256 wa = _mm256_add_ps(ra, _mm256_mul_ps(fi, dax));
                const __m256 wb = _mm256_add_ps(rb, _mm256_mul_ps(fi, dbx));
                const __m256 wq = _mm256_add_ps(rq, _mm256_mul_ps(fi, dqx));
                __m256 in = _mm256_and_ps(_mm256_cmp_ps(fi, zero, _CMP_GE_OQ), _mm256_cmp_ps(fi, span, _CMP_LE_OQ));
                in = _mm256_and_ps(in, _mm256_cmp_ps(wa, zero, _CMP_GE_OQ));
                in = _mm256_and_ps(in, _mm256_cmp_ps(wb, zero, _CMP_GE_OQ));
                in = _mm256_and_ps(in, _mm256_cmp_ps(wq, zero, _CMP_GE_OQ));
                if (_mm256_movemask_ps(in) == 0) continue;
                const __m256 k = _mm256_mul_ps(
                    _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(wa, ak), _mm256_mul_ps(wb, bk)), _mm256_mul_ps(wq, qk)), inv);
                const __m256 old = _mm256_loadu_ps(key + x);
                in = _mm256_and_ps(in, _mm256_cmp_ps(k, old, _CMP_GT_OQ));
                const int m = _mm256_movemask_ps(in);
                if (m == 0) continue;
                wrote |= m;
                _mm256_storeu_ps(key + x, _mm256_blendv_ps(old, k, in));
                const __m256i oldf = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(face + x));
                _mm256_storeu_si256(reinterpret_cast<__m256i*>(face + x),
                                    _mm256_blendv_epi8(oldf, id, _mm256_castps_si256(in)));
            }
        }
        if (wrote) {
            r.x0 = std::min(r.x0, s.i0), r.x1 = std::max(r.x1, s.i1);
            r.y0 = std::min(r.y0, s.j0), r.y1 = std::max(r.y1, s.j1);
        }
    }
    return r;
}

}  // namespace inkline
