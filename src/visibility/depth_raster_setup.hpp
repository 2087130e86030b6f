// One face's set-up for the depth buffer's kernels (depth_raster.hpp). Included by the kernel files
// only; everything here has internal linkage, so each file keeps its own copy built with its own
// instruction set.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

#include "visibility/depth_raster.hpp"

namespace inkline {
namespace {

// Pixel (i, j) has its centre at (i + 0.5, j + 0.5). A pixel of the box [i0, i1] x [j0, j1] is
// inside the face where its three edge functions are >= 0:
//   w = w0 + float(j - j0) * d_y + float(i - i0) * d_x   (evaluated in that order),
// and its key (interpolated, larger is nearer) is ((wa * ak + wb * bk) + wq * qk) * inv.
struct FaceSetup {
    int i0, i1, j0, j1;
    float wa0, wb0, wq0, da_x, db_x, dq_x, da_y, db_y, dq_y;
    float ak, bk, qk, inv;
};

// False when no pixel centre of the buffer can be inside face t (or it is degenerate).
inline bool setup_face(const RasterJob& job, const std::array<std::uint32_t, 3>& t, FaceSetup& s) {
    float ax = job.vx[t[0]], ay = job.vy[t[0]], ak = job.vk[t[0]];
    float bx = job.vx[t[1]], by = job.vy[t[1]], bk = job.vk[t[1]];
    float qx = job.vx[t[2]], qy = job.vy[t[2]], qk = job.vk[t[2]];
    const float lox = std::max(std::ceil(std::min({ax, bx, qx}) - 0.5f), 0.0f);
    const float hix = std::min(std::floor(std::max({ax, bx, qx}) - 0.5f), float(job.width - 1));
    if (!(lox <= hix)) return false;
    const float loy = std::max(std::ceil(std::min({ay, by, qy}) - 0.5f), 0.0f);
    const float hiy = std::min(std::floor(std::max({ay, by, qy}) - 0.5f), float(job.height - 1));
    if (!(loy <= hiy)) return false;
    float area = (bx - ax) * (qy - ay) - (by - ay) * (qx - ax);
    if (area == 0.0f || !std::isfinite(area)) return false;
    if (area < 0.0f) {  // counter-clockwise in the image from here on
        std::swap(bx, qx), std::swap(by, qy), std::swap(bk, qk);
        area = -area;
    }
    const float px = lox + 0.5f, py = loy + 0.5f;
    s.wa0 = (qx - bx) * (py - by) - (qy - by) * (px - bx);
    s.wb0 = (ax - qx) * (py - qy) - (ay - qy) * (px - qx);
    s.wq0 = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
    s.da_x = -(qy - by), s.db_x = -(ay - qy), s.dq_x = -(by - ay);
    s.da_y = qx - bx, s.db_y = ax - qx, s.dq_y = bx - ax;
    s.ak = ak, s.bk = bk, s.qk = qk, s.inv = 1.0f / area;
    s.i0 = int(lox), s.i1 = int(hix), s.j0 = int(loy), s.j1 = int(hiy);
    return true;
}

}  // namespace
}  // namespace inkline
