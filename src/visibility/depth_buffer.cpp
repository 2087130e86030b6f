#include "visibility/depth_buffer.hpp"

#include <algorithm>
#include <utility>

#include <glm/geometric.hpp>

#include "visibility/depth_raster.hpp"

namespace inkline {

void DepthBuffer::reset(const Camera& camera, int long_side_px, glm::dvec2 lo, glm::dvec2 hi) {
    camera_ = camera;
    ortho_ = camera.is_ortho();
    const int W = camera.width(), H = camera.height();
    const double s = double(std::max(W, H)) / double(std::max(long_side_px, 1));
    const int w = std::max(1, int(std::ceil((hi.x - lo.x) / s))), h = std::max(1, int(std::ceil((hi.y - lo.y) / s)));
    origin_ = lo;
    if (w > stride_ || h > rows_) {
        // (a multiple of 8: the vector kernel writes whole aligned groups of 8)
        stride_ = std::max((w + 7) & ~7, stride_), rows_ = std::max(h, rows_);
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
    bool any_near = false;
    for (std::size_t v = 0; v < nv; ++v) {
        const glm::dvec3 d = mesh.positions[v] - E;
        const double z = glm::dot(d, fw), x = glm::dot(d, rt), y = glm::dot(d, up);
        vnear_[v] = !(z > near);
        any_near |= !(z > near);
        const double k = ortho_ ? F : F / z;
        vx_[v] = float((cx + k * x - ox) * isx);
        vy_[v] = float((cy - k * y - oy) * isy);
        vk_[v] = float(ortho_ ? -z : 1.0 / z);
    }
    const std::size_t nf = mesh.face_count();
    if (any_near) {
        for (std::size_t f = 0; f < nf; ++f) {
            if (draw && !(*draw)[f]) continue;
            const auto& t = mesh.faces[f];
            if (vnear_[t[0]] | vnear_[t[1]] | vnear_[t[2]]) return false;
        }
    }
    const RasterJob job{vx_.data(), vy_.data(), vk_.data(), mesh.faces.data(), nf, draw ? draw->data() : nullptr,
                        key_.data(), face_.data(), stride_, width_, height_};
    const RasterResult r = kernel_(job);
    drawn_ = r.drawn;
    const int ux0 = r.x0, uy0 = r.y0, ux1 = r.x1, uy1 = r.y1;
    used_x0_ = std::min(used_x0_, ux0), used_y0_ = std::min(used_y0_, uy0);
    used_x1_ = std::max(used_x1_, ux1), used_y1_ = std::max(used_y1_, uy1);
    return true;
}

}  // namespace inkline
