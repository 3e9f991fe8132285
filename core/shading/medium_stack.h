// The media a ray path is inside, innermost last, and how a surface hit changes them.
#pragma once

#include "core/geometry/ray.h"

#include <glm/glm.hpp>

namespace caustica {

/// A small fixed-capacity stack of material indices: entering a transparent solid pushes it,
/// leaving removes it. Empty means air (index 1).
struct MediumStack {
    static constexpr int capacity = 8;
    int entries[capacity] = {};
    int size = 0;

    /// The medium the ray travels in now, or -1 for air.
    int top() const { return size > 0 ? entries[size - 1] : -1; }

    /// Enters a medium; when full the outermost entry is forgotten.
    void push(int material) {
        if (material < 0) return;
        if (size == capacity) {
            for (int i = 1; i < capacity; ++i) entries[i - 1] = entries[i];
            --size;
        }
        entries[size++] = material;
    }

    /// Leaves a medium: removes its innermost occurrence, if any.
    void remove(int material) {
        for (int i = size - 1; i >= 0; --i) {
            if (entries[i] != material) continue;
            for (int j = i + 1; j < size; ++j) entries[j - 1] = entries[j];
            --size;
            return;
        }
    }
};

/// The two media that meet where a ray crosses a transparent surface.
struct MediumTransition {
    int from = -1;          ///< medium the ray is in (material index, -1 = air)
    int to = -1;            ///< medium on the other side
    MediumStack after;      ///< the ray's stack once it has crossed (for the refracted ray)
};

/// Which media meet at a hit: the surface's inside, and its outside (explicit at a CSG union
/// interface, else whatever the ray's stack says surrounds the solid). Used alike by eye rays
/// and photons so both see the same optics.
inline MediumTransition medium_transition(const SurfaceHit& hit, const glm::vec3& direction, const MediumStack& media) {
    MediumTransition t;
    t.after = media;
    if (glm::dot(hit.normal, direction) < 0.0f) {  // entering the solid
        t.from = hit.medium_outside >= 0 ? hit.medium_outside : media.top();
        t.to = hit.medium_inside;
        if (hit.medium_outside >= 0) t.after.remove(hit.medium_outside);
        t.after.push(hit.medium_inside);
    } else {  // leaving it
        t.from = hit.medium_inside;
        t.after.remove(hit.medium_inside);
        if (hit.medium_outside >= 0 && t.after.top() != hit.medium_outside) t.after.push(hit.medium_outside);
        t.to = t.after.top();
    }
    return t;
}

}  // namespace caustica
