// A coarse depth buffer of one view, the fast visibility's first step (fast_visibility.hpp).
// Takes MeshTopology + Camera + which faces to draw; gives, per pixel of a grid laid over the
// camera's image (long side `long_side_px`, the image's aspect), the nearest drawn face at the
// pixel's centre and its depth. No exactness is claimed: a lookup is a proposal that the fast
// visibility trusts only far from any ambiguity.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/vec2.hpp>

#include "core/camera.hpp"
#include "model/topology.hpp"
#include "visibility/depth_raster.hpp"

namespace inkline {

class DepthBuffer {
public:
    // Sets the grid for `camera` and clears it (storage reused from view to view): pixels of the
    // size of a grid of `long_side_px` over the image, covering the image window [lo, hi] (image
    // pixels; it may reach beyond the image, where the model does).
    void reset(const Camera& camera, int long_side_px, glm::dvec2 lo, glm::dvec2 hi);
    // Draws the faces f with draw[f] != 0 (all faces when `draw` is null). Returns false, with the
    // buffer left partly drawn, when a face to draw reaches the camera's near plane (the caller
    // then takes the exact method: a buffer cannot stand for geometry around the eye).
    bool draw(const MeshTopology& mesh, const std::vector<std::uint8_t>* draw);
    // The fill's kernel (depth_raster.hpp; default: the fastest the CPU runs). The tests set the
    // scalar one to compare.
    void set_kernel(RasterResult (*kernel)(const RasterJob&)) { kernel_ = kernel; }
    // The buffer's raw keys (larger is nearer), row-major with stride(), for comparisons.
    const std::vector<float>& keys() const { return key_; }
    const std::vector<std::uint32_t>& faces() const { return face_; }
    int stride() const { return stride_; }

    int width() const { return width_; }
    int height() const { return height_; }
    // Camera image pixels per buffer pixel (x and y).
    glm::dvec2 scale() const { return scale_; }
    // Image point p in buffer pixels (pixel (i, j) spans [i, i+1] x [j, j+1]), and back.
    glm::dvec2 to_buffer(glm::dvec2 p) const { return (p - origin_) / scale_; }
    glm::dvec2 to_image(glm::dvec2 b) const { return origin_ + b * scale_; }
    // The face nearest at the centre of buffer pixel (i, j), kNoFace where none is; i, j in range.
    std::uint32_t face(int i, int j) const { return face_[std::size_t(j) * stride_ + i]; }
    // Its depth along the camera's view direction (+inf where no face is).
    double depth(int i, int j) const {
        const float k = key_[std::size_t(j) * stride_ + i];
        if (k == kEmpty) return std::numeric_limits<double>::infinity();
        return ortho_ ? -double(k) : 1.0 / double(k);
    }
    // Mesh vertex v's image in buffer pixels, as the last draw projected it.
    glm::vec2 vertex(std::uint32_t v) const { return {vx_[v], vy_[v]}; }
    // Faces drawn by the last draw (for statistics).
    std::size_t faces_drawn() const { return drawn_; }

private:
    // What is interpolated across a face: affine in the image (1/depth in perspective, -depth in
    // orthographic views); larger is nearer.
    static constexpr float kEmpty = -std::numeric_limits<float>::infinity();
    void clear_used();
    int width_ = 0, height_ = 0;
    int stride_ = 0, rows_ = 0;  // the storage's grid (at least width_ x height_; kept while views fit)
    glm::dvec2 scale_{1.0};
    glm::dvec2 origin_{0.0};  // image position of the buffer's corner (0, 0)
    bool ortho_ = false;
    Camera camera_;
    std::vector<float> key_;
    std::vector<std::uint32_t> face_;
    std::vector<float> vx_, vy_, vk_;  // per mesh vertex: buffer position and key
    std::vector<std::uint8_t> vnear_;  // per mesh vertex: at or before the near plane
    int used_x0_ = 0, used_y0_ = 0, used_x1_ = -1, used_y1_ = -1;  // pixels written since the clear
    std::size_t drawn_ = 0;
    RasterKernel kernel_ = raster_kernel();
};

}  // namespace inkline
