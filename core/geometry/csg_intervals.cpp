// Interval-list CSG. All three operations are one sweep over the boundaries of both
// lists in order of t, tracking which operand segments the ray is inside and which operand's
// medium fills the result there; a SegmentBuilder turns the changes into output segments,
// merging touching pieces of equal medium, dropping slivers and pairing interface ends.
#include "core/geometry/csg_intervals.h"

#include <limits>

namespace caustica {
namespace {

enum class Operation { unite, intersect, subtract };

/// The mirror image of a surface crossing: the same surface seen from the touching segment.
CsgCrossing mirror_of(const CsgCrossing& c) {
    CsgCrossing m = c;
    m.normal = -c.normal;
    m.mirrored = true;
    return m;
}

/// Collects the output segments of a sweep in order.
class SegmentBuilder {
public:
    SegmentBuilder(CsgSegmentList& out, float epsilon) : out_(out), epsilon_(epsilon) {}

    /// Adds a piece. `whole` says it is an input segment left intact (kept however short: a ray
    /// grazing a sphere); pieces the operation cut are dropped when no longer than epsilon.
    /// `enter_from_b`/`leave_from_b` say which operand each end came from (for interfaces).
    void append(CsgSegment s, bool whole, bool enter_from_b, bool leave_from_b) {
        if (!whole && !(s.leave.t - s.enter.t > epsilon_)) return;
        if (!out_.empty()) {
            CsgSegment& last = out_.back();
            if (s.enter.t - last.leave.t <= epsilon_) {  // touching (or within epsilon)
                if (last.medium == s.medium) {
                    last.leave = s.leave;
                    last_leave_from_b_ = leave_from_b;
                    return;
                }
                pair_interface(last, s, enter_from_b);
                out_.push_back(s);
                last_leave_from_b_ = leave_from_b;
                return;
            }
            last.leave.mirrored = false;
        }
        s.enter.mirrored = false;
        out_.push_back(s);
        last_leave_from_b_ = leave_from_b;
    }

    /// Completes the list: an end that touches nothing is a real surface.
    void finish() {
        if (!out_.empty()) out_.back().leave.mirrored = false;
    }

private:
    /// Makes one of the two touching ends the real surface and the other its mirror, at one t.
    /// The real one is the end already marked real, else the second operand's (it wins in a
    /// union), else the later one.
    void pair_interface(CsgSegment& last, CsgSegment& next, bool next_from_b) const {
        bool next_is_real;
        if (last.leave.mirrored != next.enter.mirrored) next_is_real = !next.enter.mirrored;
        else if (next_from_b != last_leave_from_b_) next_is_real = next_from_b;
        else next_is_real = true;
        if (next_is_real) {
            next.enter.mirrored = false;
            last.leave = mirror_of(next.enter);
        } else {
            last.leave.mirrored = false;
            next.enter = mirror_of(last.leave);
        }
    }

    CsgSegmentList& out_;
    float epsilon_;
    bool last_leave_from_b_ = false;
};

/// Which operand's medium fills the result, given the segments the ray is inside (-1 = none).
/// Returns the medium, or `none` when the point is not in the result.
constexpr int none = std::numeric_limits<int>::min();

int region_medium(Operation op, const CsgSegmentList& a, const CsgSegmentList& b, int in_a, int in_b) {
    switch (op) {
        case Operation::unite:
            if (in_b >= 0) return b[in_b].medium;  // the second operand wins
            return in_a >= 0 ? a[in_a].medium : none;
        case Operation::intersect: return (in_a >= 0 && in_b >= 0) ? a[in_a].medium : none;
        case Operation::subtract: return (in_a >= 0 && in_b < 0) ? a[in_a].medium : none;
    }
    return none;
}

/// The sweep shared by the three operations.
void sweep(Operation op, const CsgSegmentList& a, const CsgSegmentList& b, float epsilon, CsgSegmentList& out) {
    out.clear();
    SegmentBuilder builder(out, epsilon);
    const int na = a.size(), nb = b.size();
    int next_a = 0, next_b = 0;                // segment of the next boundary of each list
    bool a_leave = false, b_leave = false;     // whether that boundary is the segment's leave end
    int in_a = -1, in_b = -1;                  // segment the ray is inside, per operand
    CsgSegment piece;                          // the output segment being built
    bool piece_enter_from_b = false;
    const CsgSegment* opener = nullptr;        // input segment whose entry opened the piece, if so
    int medium = none;
    while (next_a < na || next_b < nb) {
        // Next boundary in t; at equal t leaves come before entries (so that touching faces
        // neither join a difference nor cut a union), then the first operand before the second.
        bool take_a;
        if (next_a >= na) take_a = false;
        else if (next_b >= nb) take_a = true;
        else {
            const float ta = a_leave ? a[next_a].leave.t : a[next_a].enter.t;
            const float tb = b_leave ? b[next_b].leave.t : b[next_b].enter.t;
            take_a = ta != tb ? ta < tb : (a_leave == b_leave || a_leave);
        }
        const CsgSegment& segment = take_a ? a[next_a] : b[next_b];
        const bool is_leave = take_a ? a_leave : b_leave;
        CsgCrossing c = is_leave ? segment.leave : segment.enter;
        if (take_a) {
            in_a = is_leave ? -1 : next_a;
            next_a += is_leave ? 1 : 0;
            a_leave = !a_leave;
        } else {
            in_b = is_leave ? -1 : next_b;
            next_b += is_leave ? 1 : 0;
            b_leave = !b_leave;
        }
        // The subtracted operand bounds the result from its other side.
        const bool flipped = op == Operation::subtract && !take_a;
        if (flipped) {
            c.normal = -c.normal;
            c.carved = true;
        }
        const bool leaves_region_of_segment = is_leave != flipped;  // c points out of the piece before it

        const int after = region_medium(op, a, b, in_a, in_b);
        if (after == medium) continue;  // same medium on both sides: no boundary here
        if (medium != none) {           // close the current piece
            CsgCrossing end = c;
            if (after != none && !leaves_region_of_segment) end = mirror_of(c);
            piece.leave = end;
            const bool whole = opener == &segment && is_leave && !flipped;
            builder.append(piece, whole, piece_enter_from_b, !take_a);
        }
        if (after != none) {  // open the next piece
            piece = CsgSegment{};
            piece.enter = (medium != none && leaves_region_of_segment) ? mirror_of(c) : c;
            piece.medium = after;
            piece_enter_from_b = !take_a;
            opener = (!is_leave && !flipped) ? &segment : nullptr;
        }
        medium = after;
    }
    builder.finish();
}

}  // namespace

void csg_union(const CsgSegmentList& a, const CsgSegmentList& b, float epsilon, CsgSegmentList& out) {
    if (a.empty()) {
        out = b;
        return;
    }
    if (b.empty()) {
        out = a;
        return;
    }
    sweep(Operation::unite, a, b, epsilon, out);
}

void csg_intersection(const CsgSegmentList& a, const CsgSegmentList& b, float epsilon, CsgSegmentList& out) {
    if (a.empty() || b.empty()) {
        out.clear();
        return;
    }
    sweep(Operation::intersect, a, b, epsilon, out);
}

void csg_difference(const CsgSegmentList& a, const CsgSegmentList& b, float epsilon, CsgSegmentList& out) {
    if (a.empty()) {
        out.clear();
        return;
    }
    if (b.empty()) {
        out = a;
        return;
    }
    sweep(Operation::subtract, a, b, epsilon, out);
}

bool csg_first_boundary(const CsgSegmentList& list, float tnear, float tfar, CsgBoundary& out) {
    for (int i = 0; i < list.size(); ++i) {
        const CsgSegment& s = list[i];
        if (s.enter.t >= tnear) {  // entering the solid from outside
            if (s.enter.t > tfar) return false;
            out = {&s.enter, s.medium, -1};
            return true;
        }
        if (s.leave.t < tnear) continue;
        if (s.leave.t > tfar) return false;
        const CsgSegment* next = i + 1 < list.size() ? &list[i + 1] : nullptr;
        if (next && next->enter.t == s.leave.t && (next->enter.mirrored || s.leave.mirrored)) {
            // An interface: the real surface's own segment is its inside.
            if (s.leave.mirrored) out = {&next->enter, next->medium, s.medium};
            else out = {&s.leave, s.medium, next->medium};
        } else {
            out = {&s.leave, s.medium, -1};
        }
        return true;
    }
    return false;
}

}  // namespace caustica
