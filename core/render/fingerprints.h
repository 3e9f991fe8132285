// Fingerprints of what a render's stages depend on: the keys RenderSession caches its BVH by, and
// the content key that ranks compare and animation frames reuse by. The photon stage's key is
// caustic_fingerprint (core/photons/caustic_stage.h).
#pragma once

#include "core/scene/scene_desc.h"

#include <cstdint>

namespace caustica {

/// Fingerprint of what a job renders, by content (mesh vertices, not where they are in memory;
/// the options that change the image, not -j, -s, --silent or the script's limits): the same in
/// every process that loaded the same scene with the same options. Ranks compare it before they
/// render together.
std::uint64_t job_content_fingerprint(const RenderJob& job);

/// Fingerprint of everything the BVH and materials depend on: the scene graph, materials,
/// textures, meshes (by address: a cache key within this process) and the options that feed the
/// scene stage (core/scene/options.h), not the camera or the lights.
std::uint64_t geometry_fingerprint(const RenderJob& job);

/// Fingerprint of the scene a job renders, by content, without its camera, size or the options
/// of the later stages: the geometry and materials (as job_content_fingerprint hashes them), the
/// lights, the ambient light and the background. A saved accumulation belongs to it
/// (core/render/accumulation_state.h).
std::uint64_t scene_content_fingerprint(const RenderJob& job);

}  // namespace caustica
