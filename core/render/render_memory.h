// The renderer's memory budget (--render-memory): what a render job will cost once built, checked
// before anything is built (docs/RELIABILITY.md, "Bounded memory").
#pragma once

#include "core/geometry/scene_memory.h"
#include "core/scene/scene_desc.h"
#include "core/scene/scene_flatten.h"

#include <vector>

namespace caustica {

/// What `job` (flattened as `flat`) will cost the renderer: the scene's parts (scene_memory_charges)
/// and the photon maps whose size is known before the scene is built, photon_memory_bound of the
/// photons asked for: the GI map's, and the caustic map's with --projection-map off. A caustic map
/// shot through projection maps is checked once they are built, against what the budget leaves
/// after the scene (check_photon_memory).
std::vector<MemoryCharge> render_memory_charges(const RenderJob& job, const FlatScene& flat);

/// Throws InputError, before anything is built, when render_memory_charges add up to more than the
/// job's budget (Options::render_memory_bytes): named with the line and call of the largest part,
/// with that part's bytes, the total and the budget in MiB, and the option that raises it.
void check_render_memory(const RenderJob& job, const FlatScene& flat);

}  // namespace caustica
