#include "visibility/depth_buffer.hpp"

#include <algorithm>
#include <utility>

#include <glm/geometric.hpp>

namespace inkline {

void DepthBuffer::reset(const Camera& camera, int long_side_px, glm::dvec2 lo, glm::dvec2 hi) {
    camera_ = camera;
    ortho_ = camera.is_ortho();
    const int W = camera.width(), H = camera.height();
    const double s = double(std::max(W, H)) / double(std::max(long_side_px, 1));
    const int w = std::max(1, int(std::ceil((hi.x - lo.x) / s))), h = std::max(1, int(std::ceil((hi.y - lo.y) / s)));
    origin_ = lo;
    if (w > stride_ || h > rows_) {
        stride_ = std::max(w, stride_), rows_ = std::max(h, rows_);
        key_.assign(std::size_t(stride_) * rows_, kEmpty);
        face_.assign(std::size_t(stride_) * rows_, kNoFace);
        used_x0_ = stride_, used_y0_ = rows_, used_x1_ = used_y1_ = -1;
    } else {
        clear_used();
    }
    width_ = w, height_ = h;
    scale_ = {s, s};
    drawn_ = 0;
}

void DepthBuffer::clear_used() {
    // Only the rows and columns the last view wrote: a model framed in part of the image costs
    // that part.
    for (int j = used_y0_; j <= used_y1_; ++j) {
        const std::size_t row = std::size_t(j) * stride_;
        std::fill(key_.begin() + row + used_x0_, key_.begin() + row + used_x1_ + 1, kEmpty);
        std::fill(face_.begin() + row + used_x0_, face_.begin() + row + used_x1_ + 1, kNoFace);
    }
    used_x0_ = stride_, used_y0_ = rows_, used_x1_ = used_y1_ = -1;
}

bool DepthBuffer::draw(const MeshTopology& mesh, const std::vector<std::uint8_t>* draw) {
    const std::size_t nv = mesh.vertex_count();
    vx_.resize(nv), vy_.resize(nv), vk_.resize(nv), vnear_.resize(nv);
    const glm::dvec3 E = camera_.eye(), fw = camera_.forward(), rt = camera_.right(), up = camera_.upward();
    const double F = camera_.focal(), cx = 0.5 * camera_.width(), cy = 0.5 * camera_.height();
    const double near = camera_.near_distance(), isx = 1.0 / scale_.x, isy = 1.0 / scale_.y;
    const double ox = origin_.x, oy = origin_.y;
    for (std::size_t v = 0; v < nv; ++v) {
        const glm::dvec3 d = mesh.positions[v] - E;
        const double z = glm::dot(d, fw), x = glm::dot(d, rt), y = glm::dot(d, up);
        vnear_[v] = !(z > near);
        const double k = ortho_ ? F : F / z;
        vx_[v] = float((cx + k * x - ox) * isx);
        vy_[v] = float((cy - k * y - oy) * isy);
        vk_[v] = float(ortho_ ? -z : 1.0 / z);
    }
    int ux0 = width_, uy0 = height_, ux1 = -1, uy1 = -1;
    const std::size_t nf = mesh.face_count();
    const float fw_max = float(width_ - 1), fh_max = float(height_ - 1);
    for (std::size_t f = 0; f < nf; ++f) {
        if (draw && !(*draw)[f]) continue;
        const auto& t = mesh.faces[f];
        if (vnear_[t[0]] | vnear_[t[1]] | vnear_[t[2]]) {
            used_x0_ = std::min(used_x0_, ux0), used_y0_ = std::min(used_y0_, uy0);
            used_x1_ = std::max(used_x1_, ux1), used_y1_ = std::max(used_y1_, uy1);
            return false;
        }
        ++drawn_;
        float ax = vx_[t[0]], ay = vy_[t[0]], ak = vk_[t[0]];
        float bx = vx_[t[1]], by = vy_[t[1]], bk = vk_[t[1]];
        float qx = vx_[t[2]], qy = vy_[t[2]], qk = vk_[t[2]];
        // Pixel (i, j) has its centre at (i + 0.5, j + 0.5): the centres inside the box.
        const float lox = std::max(std::ceil(std::min({ax, bx, qx}) - 0.5f), 0.0f);
        const float hix = std::min(std::floor(std::max({ax, bx, qx}) - 0.5f), fw_max);
        if (!(lox <= hix)) continue;
        const float loy = std::max(std::ceil(std::min({ay, by, qy}) - 0.5f), 0.0f);
        const float hiy = std::min(std::floor(std::max({ay, by, qy}) - 0.5f), fh_max);
        if (!(loy <= hiy)) continue;
        float area = (bx - ax) * (qy - ay) - (by - ay) * (qx - ax);
        if (area == 0.0f || !std::isfinite(area)) continue;
        if (area < 0.0f) {  // counter-clockwise in the image from here on
            std::swap(bx, qx), std::swap(by, qy), std::swap(bk, qk);
            area = -area;
        }
        const float inv = 1.0f / area;
        // Edge functions w_a (opposite a: b->q), w_b (q->a), w_q (a->b) at the box's first centre;
        // each steps by a constant along x and y.
        const float px = lox + 0.5f, py = loy + 0.5f;
        const float wa0 = (qx - bx) * (py - by) - (qy - by) * (px - bx);
        const float wb0 = (ax - qx) * (py - qy) - (ay - qy) * (px - qx);
        const float wq0 = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
        const float da_x = -(qy - by), db_x = -(ay - qy), dq_x = -(by - ay);
        const float da_y = qx - bx, db_y = ax - qx, dq_y = bx - ax;
        const int i0 = int(lox), i1 = int(hix), j0 = int(loy), j1 = int(hiy);
        bool wrote = false;
        for (int j = j0; j <= j1; ++j) {
            const float dj = float(j - j0);
            float wa = wa0 + dj * da_y, wb = wb0 + dj * db_y, wq = wq0 + dj * dq_y;
            // The row's span inside all three edges (a pixel of slack each side for rounding: the
            // test below decides), so that long thin faces cost their pixels, not their box.
            float lo = 0.0f, hi = float(i1 - i0);
            for (const auto& [w, d] : {std::pair{wa, da_x}, std::pair{wb, db_x}, std::pair{wq, dq_x}}) {
                if (d > 0.0f) lo = std::max(lo, -w / d - 1.0f);
                else if (d < 0.0f) hi = std::min(hi, -w / d + 1.0f);
                else if (w < 0.0f) hi = -1.0f;
            }
            if (!(lo <= hi)) continue;
            const int skip = int(lo);
            const int row_i0 = i0 + skip, row_i1 = i0 + int(hi);
            wa += float(skip) * da_x, wb += float(skip) * db_x, wq += float(skip) * dq_x;
            float* key = &key_[std::size_t(j) * stride_];
            std::uint32_t* face = &face_[std::size_t(j) * stride_];
            // (branch-free: which pixels of a small face's box are inside is not predictable)
            for (int i = row_i0; i <= row_i1; ++i, wa += da_x, wb += db_x, wq += dq_x) {
                const float k = (wa * ak + wb * bk + wq * qk) * inv;
                const bool in = (wa >= 0.0f) & (wb >= 0.0f) & (wq >= 0.0f) & (k > key[i]);
                key[i] = in ? k : key[i];
                face[i] = in ? std::uint32_t(f) : face[i];
                wrote |= in;
            }
        }
        if (wrote) {
            ux0 = std::min(ux0, i0), ux1 = std::max(ux1, i1);
            uy0 = std::min(uy0, j0), uy1 = std::max(uy1, j1);
        }
    }
    used_x0_ = std::min(used_x0_, ux0), used_y0_ = std::min(used_y0_, uy0);
    used_x1_ = std::max(used_x1_, ux1), used_y1_ = std::max(used_y1_, uy1);
    return true;
}

}  // namespace inkline
