// Constructive solid geometry by interval lists, as the original did it: along a ray, a solid is a
// sorted list of disjoint segments [t_in, t_out]; union, intersection and difference merge two such
// lists in one pass. Union segments also carry the medium that fills them, so that a union of a
// glass and a liquid records the glass/liquid interface that refraction needs.
#pragma once

#include <glm/glm.hpp>

#include <cstring>
#include <memory>
#include <type_traits>

namespace caustica {

/// One end of a segment: where the ray crosses a surface of a leaf primitive.
struct CsgCrossing {
    float t = 0.0f;
    /// Normal in the leaf's object space (not unit), pointing out of the segment that holds this
    /// crossing: against the ray at an entry, along it at an exit. Negated where a difference
    /// exposes the subtracted operand.
    glm::vec3 normal{0.0f};
    int material = -1;      ///< material of the surface (the leaf's)
    int leaf = -1;          ///< which leaf primitive of the CSG object the surface belongs to
    int face = 0;           ///< face code of an analytic leaf (SurfaceCrossing::face), triangle of a mesh leaf
    /// At a medium interface (two touching segments with different media) exactly one of the two
    /// touching ends is the real surface; the other is its mirror image (same t, negated normal).
    bool mirrored = false;
    /// A surface of a subtracted operand (its normal flipped by a difference, at any level): a
    /// transparent one is its own medium behind it (docs/SCENE_LANGUAGE.md, "CSG media";
    /// CsgTree::first_boundary applies this).
    bool carved = false;
};

/// The part of the ray inside a solid, with the medium (material) that fills it.
struct CsgSegment {
    CsgCrossing enter, leave;
    int medium = -1;
};

static_assert(std::is_trivially_copyable_v<CsgSegment> && std::is_trivially_destructible_v<CsgSegment>);

/// Copies a crossing field by field. The sweeps build segments on the stack with narrow stores and
/// then copy them; a whole-struct copy reads them back in 16-byte loads, which store forwarding
/// cannot serve from the narrow stores just made (a stall of a dozen cycles each).
inline void copy_crossing(CsgCrossing& to, const CsgCrossing& from) {
    to.t = from.t;
    to.normal.x = from.normal.x;
    to.normal.y = from.normal.y;
    to.normal.z = from.normal.z;
    to.material = from.material;
    to.leaf = from.leaf;
    to.face = from.face;
    to.mirrored = from.mirrored;
    to.carved = from.carved;
}

/// copy_crossing for a whole segment.
inline void copy_segment(CsgSegment& to, const CsgSegment& from) {
    copy_crossing(to.enter, from.enter);
    copy_crossing(to.leave, from.leave);
    to.medium = from.medium;
}

/// A growable list of segments that keeps the first `inline_capacity` in place (no heap
/// allocation in the common case: this runs per ray per CSG node) and moves to the heap beyond.
class CsgSegmentList {
public:
    static constexpr int inline_capacity = 8;

    /// An empty list (its inline storage stays uninitialised).
    CsgSegmentList() = default;
    /// Copies the segments (into inline storage when they fit).
    CsgSegmentList(const CsgSegmentList& other) { assign(other); }
    CsgSegmentList& operator=(const CsgSegmentList& other) {
        if (this != &other) assign(other);
        return *this;
    }
    ~CsgSegmentList() = default;

    /// Appends a segment (callers keep the list sorted and disjoint).
    void push_back(const CsgSegment& s) {
        if (size_ == capacity_) grow();
        copy_segment(data_[size_++], s);
    }
    /// Appends a segment whose fields the caller then writes in place (its contents are
    /// unspecified until then): no temporary to copy.
    CsgSegment& append() {
        if (size_ == capacity_) grow();
        return data_[size_++];
    }
    /// Empties the list (keeps any heap storage).
    void clear() { size_ = 0; }
    // Size, element access and iteration, as std::vector's.
    int size() const { return size_; }
    bool empty() const { return size_ == 0; }
    CsgSegment& operator[](int i) { return data_[i]; }
    const CsgSegment& operator[](int i) const { return data_[i]; }
    CsgSegment& back() { return data_[size_ - 1]; }
    const CsgSegment& back() const { return data_[size_ - 1]; }
    const CsgSegment* begin() const { return data_; }
    const CsgSegment* end() const { return data_ + size_; }
    /// Whether the segments have moved to the heap (for tests).
    bool on_heap() const { return heap_ != nullptr; }

private:
    void assign(const CsgSegmentList& other) {
        size_ = 0;
        while (capacity_ < other.size_) grow();
        std::memcpy(static_cast<void*>(data_), other.data_, sizeof(CsgSegment) * static_cast<std::size_t>(other.size_));
        size_ = other.size_;
    }
    void grow() {
        const int capacity = capacity_ * 2;
        std::unique_ptr<CsgSegment[]> bigger(new CsgSegment[static_cast<std::size_t>(capacity)]);
        std::memcpy(static_cast<void*>(bigger.get()), data_, sizeof(CsgSegment) * static_cast<std::size_t>(size_));
        heap_ = std::move(bigger);
        data_ = heap_.get();
        capacity_ = capacity;
    }

    alignas(CsgSegment) unsigned char inline_[sizeof(CsgSegment) * inline_capacity];  // uninitialised until used
    CsgSegment* data_ = reinterpret_cast<CsgSegment*>(inline_);
    std::unique_ptr<CsgSegment[]> heap_;
    int size_ = 0;
    int capacity_ = inline_capacity;
};

/// Points of either operand. Where both are present the second operand's medium wins, and where
/// the medium changes inside the solid the result has two touching segments (an interface): where
/// a segment of one operand begins or ends inside the other's, or ends within `epsilon` of the
/// beginning of the other's. Touching segments of equal media are merged (A u A = A).
void csg_union(const CsgSegmentList& a, const CsgSegmentList& b, float epsilon, CsgSegmentList& out);

/// Points of both operands; the medium is the first operand's. Pieces no longer than `epsilon`
/// that the operation cut (not whole input segments) are dropped, as are zero-length contacts.
void csg_intersection(const CsgSegmentList& a, const CsgSegmentList& b, float epsilon, CsgSegmentList& out);

/// Points of `a` not in `b`. Surfaces exposed by `b` keep b's material with their normals flipped
/// and are marked `carved`; the segments' medium is a's. Slivers no longer than `epsilon` are
/// dropped (A - A is empty).
void csg_difference(const CsgSegmentList& a, const CsgSegmentList& b, float epsilon, CsgSegmentList& out);

/// The first surface of a segment list at or after `tnear` (and not after `tfar`), with the
/// media on its two sides. `surface` is the real surface (never a mirror copy); its normal points
/// from `medium_inside` to `medium_outside` (-1 = outside the whole solid).
struct CsgBoundary {
    const CsgCrossing* surface = nullptr;
    int medium_inside = -1;
    int medium_outside = -1;
};

/// Finds the first boundary in [tnear, tfar]; a ray starting inside a segment finds its exit.
bool csg_first_boundary(const CsgSegmentList& list, float tnear, float tfar, CsgBoundary& out);

}  // namespace caustica
