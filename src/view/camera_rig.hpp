// The preview window's camera: orbit, pan and zoom with the mouse, the standard views, and
// perspective/orthographic, kept as eye, target and up (the DESIGN.md camera), so any state gives
// the exact `inkline render` flags. No GL here.
#pragma once

#include <string>

#include <glm/vec3.hpp>

#include "core/camera.hpp"

namespace inkline {

class CameraRig {
public:
    // `home` is where reset() returns; `box` frames the front/side/top views.
    CameraRig(const Camera& home, const Bounds3& box);

    // Turns the eye around the target: `yaw_deg` about the home up axis, `pitch_deg` about the
    // camera's right axis (the up vector turns with it, so looking straight down is fine).
    void orbit(double yaw_deg, double pitch_deg);
    // Moves eye and target together by (dx, dy) pixels of an image `height` pixels high
    // (the point under the cursor at the target's depth follows the cursor).
    void pan(double dx_px, double dy_px, int height);
    // Distance to the target (and the orthographic height) times 0.9^steps.
    void zoom(double steps);
    void reset();
    void front();  // looking along -Z, up +Y (eye on the +Z side of the model)
    void side();   // looking along -X, up +Y
    void top();    // looking down -Y, up -Z
    // Orthographic keeps the size of the target plane on screen.
    void toggle_ortho();

    bool ortho() const { return ortho_; }
    glm::dvec3 eye() const { return eye_; }
    glm::dvec3 target() const { return target_; }
    glm::dvec3 up() const { return up_; }
    // The camera for an image of width x height pixels (near plane left to the session's default).
    Camera camera(int width, int height) const;

private:
    void look(const glm::dvec3& dir, const glm::dvec3& up);
    Camera home_;
    Bounds3 box_;
    glm::dvec3 eye_, target_, up_, axis_;
    double fov_ = 30.0, ortho_height_ = 1.0, distance_home_ = 1.0;
    bool ortho_ = false;
};

// The camera flags exactly as `inkline render` prints them (without the leading "camera: ").
std::string camera_flags(const Camera& camera);

}  // namespace inkline
