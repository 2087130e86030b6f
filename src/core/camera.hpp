// Camera of DESIGN.md: eye E, target T, up U, vertical fov, image W x H pixels,
// perspective or orthographic. Pixel coordinates are continuous, origin top-left, y down.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace inkline {

struct Bounds3 {
    glm::dvec3 lo{0.0}, hi{0.0};
    glm::dvec3 center() const { return 0.5 * (lo + hi); }
    double half_diagonal() const;
};

class Camera {
public:
    // Perspective camera. Throws std::invalid_argument for a degenerate frame
    // (eye == target, up parallel to the view direction, fov outside (0,180), empty image).
    static Camera perspective(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, double fov_deg,
                              int width, int height);
    // Orthographic camera: `ortho_height` world units fill the image height.
    static Camera orthographic(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up,
                               double ortho_height, int width, int height);
    // DESIGN.md default framing: target = box centre, R = half diagonal,
    // eye = target + normalize(1, 0.6, 1.4) * R / sin(fov/2), up = +Y, fov = 30.
    static Camera framing(const Bounds3& box, int width, int height, double fov_deg = 30.0);

    glm::dvec3 eye() const { return eye_; }
    glm::dvec3 target() const { return target_; }
    glm::dvec3 up() const { return up_; }
    double fov_deg() const { return fov_deg_; }
    bool is_ortho() const { return ortho_; }
    double ortho_height() const { return ortho_height_; }
    int width() const { return width_; }
    int height() const { return height_; }
    glm::dvec3 forward() const { return f_; }
    glm::dvec3 right() const { return r_; }
    glm::dvec3 upward() const { return u_; }
    // F of DESIGN.md: pixels per unit of (lateral distance / depth), or per world unit (ortho).
    double focal() const { return focal_; }

    // Signed distance along the view direction from the eye plane.
    // (depth and project are inline: the crossing search and the walks call them per vertex)
    double depth(const glm::dvec3& p) const { return glm::dot(p - eye_, f_); }
    // Pixel coordinates; for perspective only meaningful when depth(p) > 0.
    glm::dvec2 project(const glm::dvec3& p) const {
        const glm::dvec3 d = p - eye_;
        const double x = glm::dot(d, r_), y = glm::dot(d, u_);
        if (ortho_) return {0.5 * width_ + focal_ * x, 0.5 * height_ - focal_ * y};
        const double z = glm::dot(d, f_);
        return {0.5 * width_ + focal_ * x / z, 0.5 * height_ - focal_ * y / z};
    }
    // Near plane distance used to clip geometry behind or at the eye (perspective and ortho).
    // It is a camera parameter: by default a fixed fraction of the scene size (see set_near).
    double near_distance() const { return near_; }
    void set_near(double d) { near_ = d; }
    // Where a line of sight towards p starts: the eye (perspective) or the foot of p on the
    // eye plane (orthographic).
    glm::dvec3 ray_origin(const glm::dvec3& p) const;

private:
    void finish();
    glm::dvec3 eye_{0.0}, target_{0.0, 0.0, -1.0}, up_{0.0, 1.0, 0.0};
    double fov_deg_ = 30.0;
    bool ortho_ = false;
    double ortho_height_ = 0.0;
    int width_ = 1024, height_ = 1024;
    glm::dvec3 f_{0.0}, r_{0.0}, u_{0.0};
    double focal_ = 1.0;  // F = (H/2)/tan(fov/2) for perspective, H/ortho_height for ortho
    double near_ = 0.0;
};

}  // namespace inkline
