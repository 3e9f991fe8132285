// The media a ray path is inside, innermost last (material indices; empty = air, index 1).
#pragma once

namespace caustica {

/// A small fixed-capacity stack: entering a transparent solid pushes it, leaving removes it.
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

}  // namespace caustica
