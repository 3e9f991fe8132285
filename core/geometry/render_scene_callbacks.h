// The Embree user geometries of a RenderScene: callbacks that intersect its analytic primitives
// and its CSG objects, and the data they read. Internal to render_scene.cpp.
#pragma once

#include "core/geometry/render_scene.h"

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

namespace caustica::user_geometry {

/// What the analytic user geometry's callbacks read.
/// With `brute_force` (--disable-bv) the geometry is one primitive holding them all, bounded by
/// their union, so every ray that reaches it tests every primitive: no bounding volumes.
struct AnalyticGeometry {
    const RenderScene::AnalyticPrimitive* prims;
    const glm::vec3* lo;
    const glm::vec3* hi;
    unsigned count = 0;
    bool brute_force = false;

    /// The primitives an Embree primitive stands for.
    unsigned first(unsigned prim_id) const { return brute_force ? 0u : prim_id; }
    unsigned last(unsigned prim_id) const { return brute_force ? count : prim_id + 1; }
};

/// Bounds, intersect and occluded callbacks of the analytic user geometry (user data: AnalyticGeometry).
void analytic_bounds(const RTCBoundsFunctionArguments* args);
void analytic_intersect(const RTCIntersectFunctionNArguments* args);
void analytic_occluded(const RTCOccludedFunctionNArguments* args);

/// What a CSG hit leaves for fill_hit (Embree's hit record has no room for the leaf and media).
struct CsgHitRecord {
    int leaf = -1, face = 0, material = -1, medium_inside = -1, medium_outside = -1;
};

/// The record csg_intersect left for ray `lane` of the last query on this thread (lane 0 for one ray).
const CsgHitRecord& csg_hit_record(int lane);

/// What the CSG user geometry's callbacks read.
struct CsgGeometry {
    const CsgTree* trees;
};

/// Bounds, intersect and occluded callbacks of the CSG user geometry (user data: CsgGeometry).
void csg_bounds(const RTCBoundsFunctionArguments* args);
void csg_intersect(const RTCIntersectFunctionNArguments* args);
void csg_occluded(const RTCOccludedFunctionNArguments* args);

}  // namespace caustica::user_geometry
