// Checks that a render job stays inside the numeric range the renderer computes in, before
// anything is built: a hostile but finite scene gets a "file:line: call: message" error instead
// of a float overflow, a NaN pixel or an Embree assertion. Both `caustica render` and the preview
// run every job through here (RenderSession::prepare).
#pragma once

#include "core/util/radiance_range.h"
#include "core/scene/scene_desc.h"
#include "core/scene/scene_flatten.h"

namespace caustica {

/// Largest |coordinate| of the eye, a light (centre plus radius), a translation, a scale factor
/// and any point of the geometry in world space. Embree refuses rays whose origin or direction
/// has a component above FLT_LARGE = 1.844e18 (its ray-validity assertion aborts the process),
/// and the renderer forms differences of two points and squared lengths of those, up to
/// 3 x (2e18)^2 = 1.2e37 < FLT_MAX: both hold with every coordinate within 1e18.
inline constexpr double max_coordinate = 1e18;

/// Range of a non-zero light falloff coefficient: c0 = 1e-308 is zero once in float, which makes
/// the attenuation 1 / 0. Zero itself is allowed (not all three).
inline constexpr double min_falloff = 1e-30, max_falloff = 1e30;

/// Range of refractive indices: the ratio of two stays within 1e12, its square within float.
inline constexpr double min_refractive_index = 1e-6, max_refractive_index = 1e6;

/// Largest Phong exponent: (r.v)^n is already 0 in float for any r.v < 1 long before this.
inline constexpr double max_shininess = 1e6;

/// Largest power a caustic photon may start with (colour x 4 pi u^2 x fudge / (c2 x photons),
/// docs/CAUSTICS.md, "Photon energy"): far above anything visible, and saturated sums of such
/// powers stay finite.
inline constexpr double max_photon_power = 1e30;

/// How a script names the call that made a node of `kind` ("gr.sphere"), for messages.
const char* node_call(NodeKind kind);

/// Checks the numeric options, camera, lights, materials, ambient and miss colours, node
/// parameters and transform calls of a job, and the photon power its options give each light. Throws InputError naming
/// the line of the entity at fault (the camera's is the gr.render line).
void validate_render_job(const RenderJob& job);

/// Checks that every flattened primitive lies within max_coordinate in world space (and that its
/// inverse transform is representable in float). Throws InputError naming the node's line.
void validate_flat_scene(const FlatScene& flat, const SceneDesc& scene);

}  // namespace caustica
