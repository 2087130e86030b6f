#include "view/camera_rig.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

namespace inkline {
namespace {
glm::dvec3 turn(const glm::dvec3& v, const glm::dvec3& axis, double degrees) {
    return glm::angleAxis(glm::radians(degrees), glm::normalize(axis)) * v;
}
}  // namespace

CameraRig::CameraRig(const Camera& home, const Bounds3& box) : home_(home), box_(box) {
    axis_ = glm::normalize(home.up());
    distance_home_ = glm::length(home.target() - home.eye());
    reset();
}

void CameraRig::reset() {
    eye_ = home_.eye();
    target_ = home_.target();
    up_ = home_.upward();
    ortho_ = home_.is_ortho();
    fov_ = home_.is_ortho() ? 30.0 : home_.fov_deg();
    ortho_height_ = home_.is_ortho() ? home_.ortho_height()
                                     : 2.0 * distance_home_ * std::tan(glm::radians(fov_) / 2.0);
}

void CameraRig::orbit(double yaw_deg, double pitch_deg) {
    glm::dvec3 offset = eye_ - target_;
    if (yaw_deg != 0.0) {
        offset = turn(offset, axis_, yaw_deg);
        up_ = turn(up_, axis_, yaw_deg);
    }
    if (pitch_deg != 0.0) {
        const glm::dvec3 right = glm::cross(-offset, up_);
        if (glm::length(right) > 0.0) {
            offset = turn(offset, right, pitch_deg);
            up_ = turn(up_, right, pitch_deg);
        }
    }
    eye_ = target_ + offset;
    const glm::dvec3 f = glm::normalize(-offset), r = glm::normalize(glm::cross(f, up_));
    up_ = glm::cross(r, f);  // kept orthonormal against drift
}

void CameraRig::pan(double dx_px, double dy_px, int height) {
    const glm::dvec3 f = glm::normalize(target_ - eye_), r = glm::normalize(glm::cross(f, up_)), u = glm::cross(r, f);
    const double world_height =
        ortho_ ? ortho_height_ : 2.0 * glm::length(target_ - eye_) * std::tan(glm::radians(fov_) / 2.0);
    const double s = world_height / std::max(1, height);
    const glm::dvec3 d = -dx_px * s * r + dy_px * s * u;
    eye_ += d;
    target_ += d;
}

void CameraRig::zoom(double steps) {
    const double k = std::pow(0.9, steps);
    const double dist = glm::length(eye_ - target_) * k;
    if (!(dist > 1e-9 * distance_home_) || !std::isfinite(dist)) return;
    eye_ = target_ + (eye_ - target_) * k;
    ortho_height_ *= k;
}

void CameraRig::look(const glm::dvec3& dir, const glm::dvec3& up) {
    target_ = box_.center();
    const double dist = glm::length(eye_ - target_);
    eye_ = target_ + dir * dist;
    up_ = up;
}

void CameraRig::front() { look({0, 0, 1}, {0, 1, 0}); }
void CameraRig::side() { look({1, 0, 0}, {0, 1, 0}); }
void CameraRig::top() { look({0, 1, 0}, {0, 0, -1}); }

void CameraRig::toggle_ortho() {
    const double dist = glm::length(target_ - eye_);
    if (ortho_) {
        // Back to perspective at a distance that keeps the target plane's size.
        const double d = ortho_height_ / (2.0 * std::tan(glm::radians(fov_) / 2.0));
        eye_ = target_ + glm::normalize(eye_ - target_) * d;
    } else {
        ortho_height_ = 2.0 * dist * std::tan(glm::radians(fov_) / 2.0);
    }
    ortho_ = !ortho_;
}

Camera CameraRig::camera(int width, int height) const {
    Camera c = ortho_ ? Camera::orthographic(eye_, target_, up_, ortho_height_, width, height)
                      : Camera::perspective(eye_, target_, up_, fov_, width, height);
    if (home_.near_distance() > 0.0) c.set_near(home_.near_distance());  // a --near given by the user
    return c;
}

std::string camera_flags(const Camera& cam) {
    const auto v3 = [](const glm::dvec3& v) {
        char buf[128];
        std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g", v.x, v.y, v.z);
        return std::string(buf);
    };
    char buf[512];
    std::snprintf(buf, sizeof buf, "--eye=%s --target=%s --up=%s --%s=%.17g --size=%dx%d", v3(cam.eye()).c_str(),
                  v3(cam.target()).c_str(), v3(cam.up()).c_str(), cam.is_ortho() ? "ortho" : "fov",
                  cam.is_ortho() ? cam.ortho_height() : cam.fov_deg(), cam.width(), cam.height());
    return buf;
}

}  // namespace inkline
