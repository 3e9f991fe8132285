// The course's pinhole camera: eye, view direction, up vector, and gr.render's field of view,
// which is the horizontal angle (docs/SCENE_LANGUAGE.md, "camera angle").
#pragma once

#include "core/geometry/ray.h"
#include "core/scene/scene_desc.h"

namespace caustica {

/// The vertical field of view of a width x height image, in degrees: gr.render's angle is the
/// horizontal one and fov_y = fov_x / aspect, aspect = width / height. Camera keeps the
/// angle it uses below 179 degrees (a tall image with a wide angle would reach 180).
double vertical_fov_degrees(const CameraDesc& desc, int width, int height);

/// Generates primary rays through pixel positions (x right, y down, pixel centres at +0.5).
class Camera {
public:
    Camera(const CameraDesc& desc, int width, int height);

    /// The ray through image position (x, y) in pixels.
    Ray generate(float x, float y) const;

    /// The image position of a world point, or false when it is behind the eye.
    bool project(const glm::vec3& world, glm::vec2& pixel) const;

private:
    glm::vec3 eye_, right_, up_, forward_;
    float half_width_, half_height_;  // tan-scaled image plane half extents at distance 1
    int width_, height_;
};

}  // namespace caustica
