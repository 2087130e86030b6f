#include "core/camera.hpp"

#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace inkline {

double Bounds3::half_diagonal() const { return 0.5 * glm::length(hi - lo); }

static bool finite3(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void Camera::finish() {
    if (width_ <= 0 || height_ <= 0) throw std::invalid_argument("image size must be positive");
    if (!finite3(eye_) || !finite3(target_) || !finite3(up_))
        throw std::invalid_argument("camera vectors must be finite");
    const glm::dvec3 d = target_ - eye_;
    if (glm::length(d) == 0.0) throw std::invalid_argument("camera eye and target coincide");
    f_ = glm::normalize(d);
    const glm::dvec3 c = glm::cross(f_, up_);
    const double cl = glm::length(c);
    if (!(cl > 1e-12 * glm::length(up_)))
        throw std::invalid_argument("camera up vector is zero or parallel to the view direction");
    r_ = c / cl;
    u_ = glm::cross(r_, f_);
    if (ortho_) {
        if (!(ortho_height_ > 0.0) || !std::isfinite(ortho_height_))
            throw std::invalid_argument("orthographic height must be positive");
        focal_ = double(height_) / ortho_height_;
    } else {
        if (!(fov_deg_ > 0.0 && fov_deg_ < 180.0))
            throw std::invalid_argument("field of view must be in (0, 180) degrees");
        focal_ = (0.5 * height_) / std::tan(0.5 * fov_deg_ * M_PI / 180.0);
    }
}

Camera Camera::perspective(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, double fov_deg,
                           int width, int height) {
    Camera c;
    c.eye_ = eye;
    c.target_ = target;
    c.up_ = up;
    c.fov_deg_ = fov_deg;
    c.width_ = width;
    c.height_ = height;
    c.ortho_ = false;
    c.finish();
    return c;
}

Camera Camera::orthographic(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, double ortho_height,
                            int width, int height) {
    Camera c;
    c.eye_ = eye;
    c.target_ = target;
    c.up_ = up;
    c.ortho_ = true;
    c.ortho_height_ = ortho_height;
    c.width_ = width;
    c.height_ = height;
    c.finish();
    return c;
}

Camera Camera::framing(const Bounds3& box, int width, int height, double fov_deg) {
    const glm::dvec3 t = box.center();
    double R = box.half_diagonal();
    if (!(R > 0.0)) R = 1.0;
    const double s = std::sin(0.5 * fov_deg * M_PI / 180.0);
    const glm::dvec3 eye = t + glm::normalize(glm::dvec3(1.0, 0.6, 1.4)) * (R / s);
    return perspective(eye, t, {0.0, 1.0, 0.0}, fov_deg, width, height);
}

glm::dvec3 Camera::ray_origin(const glm::dvec3& p) const {
    if (!ortho_) return eye_;
    return p - f_ * depth(p);
}

}  // namespace inkline
