// An orbit camera: the script's eye and view direction, orbited around a target point on the
// view axis. The preview drags it (ui/); `caustica render --orbit-frames` turns it (app/animation).
#pragma once

#include "core/scene/scene_desc.h"

#include <glm/glm.hpp>

namespace caustica {

/// An orbit camera that starts as the script's camera and returns to it exactly on reset.
class OrbitCamera {
public:
    OrbitCamera() = default;
    /// Starts at `script`, with the target `target_distance` along the view direction.
    OrbitCamera(const CameraDesc& script, double target_distance);

    /// Moves the eye around the target: +yaw to the camera's right around the script's up
    /// vector, +pitch upwards (stopping 1 degree short of the poles). Degrees.
    void orbit(double yaw_degrees, double pitch_degrees);

    /// Multiplies the eye-to-target distance by `factor` (< 1 moves closer); the target stays.
    void zoom(double factor);

    /// Moves eye and target across the view so that the target plane follows the cursor by
    /// (dx, dy) pixels of an image `image_width` x `image_height` pixels (y down).
    void pan_pixels(glm::dvec2 pixels, int image_width, int image_height);

    /// Aims at `target`, keeping the eye where it is.
    void set_target(const glm::dvec3& target);

    /// Moves the target along the current view axis to `distance` from the eye.
    void set_target_distance(double distance);

    /// The camera to render with (bit-identical to the script's until the camera is moved).
    CameraDesc desc() const;

    /// The script's camera this orbit started from.
    const CameraDesc& script_camera() const { return script_; }

    /// Whether the camera differs from the script's.
    bool moved() const { return moved_; }

    /// The point orbited around.
    glm::dvec3 target() const { return target_; }
    /// The eye point.
    glm::dvec3 eye() const { return eye_; }
    /// Distance from the eye to the target.
    double distance() const { return glm::length(target_ - eye_); }

private:
    CameraDesc script_;
    glm::dvec3 eye_{0.0, 0.0, 1.0}, target_{0.0}, up_{0.0, 1.0, 0.0};
    bool moved_ = false;
};

/// A target distance for a camera whose view ray hits nothing: where the ray passes closest to
/// the world origin, or 1 when that is behind the eye.
double default_target_distance(const CameraDesc& camera);

}  // namespace caustica
