// Where an orbit turns: the depth, along the camera's view axis, of the centre of what the camera
// sees. The preview's orbit camera and `caustica render --orbit-frames` start from it
// (docs/PREVIEW.md, "Keys and mouse"; docs/ANIMATION.md, "The target").
#pragma once

#include "core/geometry/ray.h"
#include "core/scene/scene_desc.h"

#include <glm/glm.hpp>

#include <functional>

namespace caustica {

class RenderSession;

/// The first surface point along a ray, as RenderSession::pick finds it.
using PickFunction = std::function<bool(const Ray& ray, glm::vec3& point)>;

/// The distance from the eye, along the view direction, to the centre of the bounds of the
/// surfaces a grid of view rays across a `width` x `height` image meets (each axis trimmed of
/// its nearest and farthest 5 %, so a ground plane to the horizon does not pull the centre away).
/// 0 when no ray meets anything or that centre lies behind the eye.
double visible_centre_distance(const PickFunction& pick, const CameraDesc& camera, int width, int height);

/// The same through the scene `session` built last.
double visible_centre_distance(const RenderSession& session, const CameraDesc& camera, int width, int height);

}  // namespace caustica
