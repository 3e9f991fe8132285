#include "core/geometry/render_scene_callbacks.h"

#include "core/util/cancel_flag.h"

#include <cmath>

namespace caustica::user_geometry {
namespace {

/// Whether a normal Embree may report: finite, and within its hit check's FLT_LARGE.
bool finite_normal(const glm::vec3& n) {
    return std::fabs(n.x) <= embree_coordinate_limit && std::fabs(n.y) <= embree_coordinate_limit &&
           std::fabs(n.z) <= embree_coordinate_limit;
}

/// The crossing of a primitive nearest the ray start inside [tnear, tfar], if any.
const SurfaceCrossing* nearest_crossing(const RenderScene::AnalyticPrimitive& prim, const glm::vec3& o,
                                        const glm::vec3& d, float tnear, float tfar, ShapeInterval& interval) {
    if (prim.world_space) {
        if (!intersect_shape_interval(prim.shape, o, d, interval)) return nullptr;
    } else {
        const glm::vec3 oo = glm::vec3(prim.world_to_object * glm::vec4(o, 1.0f));
        const glm::vec3 dd = glm::mat3(prim.world_to_object) * d;
        if (!intersect_shape_interval(prim.shape, oo, dd, interval)) return nullptr;
    }
    // Only finite distances: a shape far from a line, or under an extreme transform, can yield an
    // infinite or NaN root, which must never become a hit (Embree would trace from infinity next).
    if (interval.entry.t >= tnear && interval.entry.t <= tfar && std::isfinite(interval.entry.t)) return &interval.entry;
    if (interval.exit.t >= tnear && interval.exit.t <= tfar && std::isfinite(interval.exit.t)) return &interval.exit;
    return nullptr;
}

/// The cancel flag of the query a callback serves: every RenderScene query passes a RayQueryContext.
const std::atomic<bool>* query_cancel(const RTCIntersectContext* context) {
    return reinterpret_cast<const RayQueryContext*>(context)->cancel;
}

/// Ends ray i of a cancelled query: with a negative tfar Embree skips everything the ray has left
/// to visit (for occlusion it also means blocked); RenderScene reports the query as stopped.
void end_cancelled_ray(RTCRayN* ray, unsigned n, unsigned i) { RTCRayN_tfar(ray, n, i) = -ray_infinity; }

/// The first boundary of `tree` along ray i of a query; false once the query is cancelled (the
/// tree reads the flag at every leaf, and after it its list is not the solid's).
bool boundary_along_ray(const CsgTree& tree, RTCRayN* ray, unsigned n, unsigned i, const std::atomic<bool>* cancel,
                        CsgSegmentList& list, CsgBoundary& boundary) {
    if (is_cancelled(cancel)) return false;
    const glm::vec3 o(RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i));
    const glm::vec3 d(RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i));
    return tree.first_boundary(o, d, RTCRayN_tnear(ray, n, i), RTCRayN_tfar(ray, n, i), list, boundary, cancel);
}

/// One record per ray of a packet and per thread: the CSG intersect callback writes it for each
/// hit it accepts (so the last write is the final hit's), and fill_hit reads it right after the
/// query on the same thread (Embree runs a query's callbacks on the thread that asked).
thread_local CsgHitRecord csg_records[8];

}  // namespace

void analytic_bounds(const RTCBoundsFunctionArguments* args) {
    const auto* geometry = static_cast<const AnalyticGeometry*>(args->geometryUserPtr);
    glm::vec3 lo = geometry->lo[args->primID], hi = geometry->hi[args->primID];
    if (geometry->brute_force)
        for (unsigned i = 0; i < geometry->count; ++i) lo = glm::min(lo, geometry->lo[i]), hi = glm::max(hi, geometry->hi[i]);
    RTCBounds* b = args->bounds_o;
    b->lower_x = lo.x, b->lower_y = lo.y, b->lower_z = lo.z;
    b->upper_x = hi.x, b->upper_y = hi.y, b->upper_z = hi.z;
}

void analytic_intersect(const RTCIntersectFunctionNArguments* args) {
    const auto* geometry = static_cast<const AnalyticGeometry*>(args->geometryUserPtr);
    const std::atomic<bool>* cancel = query_cancel(args->context);
    const unsigned n = args->N;
    RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, n);
    RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, n);
    for (unsigned i = 0; i < n; ++i)
      for (unsigned p = geometry->first(args->primID); p < geometry->last(args->primID); ++p) {
        const RenderScene::AnalyticPrimitive& prim = geometry->prims[p];
        if (args->valid[i] != -1) continue;
        if (is_cancelled(cancel)) {
            end_cancelled_ray(ray, n, i);
            break;
        }
        const glm::vec3 o(RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i));
        const glm::vec3 d(RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i));
        ShapeInterval interval;
        const SurfaceCrossing* c =
            nearest_crossing(prim, o, d, RTCRayN_tnear(ray, n, i), RTCRayN_tfar(ray, n, i), interval);
        if (!c) continue;
        const glm::vec3 normal = prim.normal_to_world * c->normal;
        if (!finite_normal(normal)) continue;
        RTCRayN_tfar(ray, n, i) = c->t;
        RTCHitN_Ng_x(hit, n, i) = normal.x;
        RTCHitN_Ng_y(hit, n, i) = normal.y;
        RTCHitN_Ng_z(hit, n, i) = normal.z;
        RTCHitN_u(hit, n, i) = static_cast<float>(c->face);
        RTCHitN_v(hit, n, i) = 0.0f;
        RTCHitN_primID(hit, n, i) = p;
        RTCHitN_geomID(hit, n, i) = args->geomID;
        for (unsigned level = 0; level < RTC_MAX_INSTANCE_LEVEL_COUNT; ++level)
            RTCHitN_instID(hit, n, i, level) = args->context->instID[level];
      }
}

void analytic_occluded(const RTCOccludedFunctionNArguments* args) {
    const auto* geometry = static_cast<const AnalyticGeometry*>(args->geometryUserPtr);
    const std::atomic<bool>* cancel = query_cancel(args->context);
    const unsigned n = args->N;
    for (unsigned i = 0; i < n; ++i)
      for (unsigned p = geometry->first(args->primID); p < geometry->last(args->primID); ++p) {
        const RenderScene::AnalyticPrimitive& prim = geometry->prims[p];
        if (args->valid[i] != -1 || RTCRayN_tfar(args->ray, n, i) < 0.0f) continue;
        if (is_cancelled(cancel)) {
            end_cancelled_ray(args->ray, n, i);
            break;
        }
        const glm::vec3 o(RTCRayN_org_x(args->ray, n, i), RTCRayN_org_y(args->ray, n, i),
                          RTCRayN_org_z(args->ray, n, i));
        const glm::vec3 d(RTCRayN_dir_x(args->ray, n, i), RTCRayN_dir_y(args->ray, n, i),
                          RTCRayN_dir_z(args->ray, n, i));
        ShapeInterval interval;
        if (nearest_crossing(prim, o, d, RTCRayN_tnear(args->ray, n, i), RTCRayN_tfar(args->ray, n, i), interval))
            RTCRayN_tfar(args->ray, n, i) = -ray_infinity;
      }
}

const CsgHitRecord& csg_hit_record(int lane) { return csg_records[lane & 7]; }

void csg_bounds(const RTCBoundsFunctionArguments* args) {
    const auto* geometry = static_cast<const CsgGeometry*>(args->geometryUserPtr);
    const CsgTree& tree = geometry->trees[args->primID];
    const glm::vec3 lo = tree.lo(), hi = tree.hi();
    RTCBounds* b = args->bounds_o;
    b->lower_x = lo.x, b->lower_y = lo.y, b->lower_z = lo.z;
    b->upper_x = hi.x, b->upper_y = hi.y, b->upper_z = hi.z;
}

void csg_intersect(const RTCIntersectFunctionNArguments* args) {
    const auto* geometry = static_cast<const CsgGeometry*>(args->geometryUserPtr);
    const CsgTree& tree = geometry->trees[args->primID];
    const std::atomic<bool>* cancel = query_cancel(args->context);
    const unsigned n = args->N;
    RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, n);
    RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, n);
    for (unsigned i = 0; i < n; ++i) {
        if (args->valid[i] != -1) continue;
        CsgSegmentList list;
        CsgBoundary boundary;
        const bool met = boundary_along_ray(tree, ray, n, i, cancel, list, boundary);
        if (is_cancelled(cancel)) {
            end_cancelled_ray(ray, n, i);
            continue;
        }
        if (!met) continue;
        const CsgCrossing& surface = *boundary.surface;
        const glm::vec3 normal = tree.leaf(surface.leaf).normal_to_world * surface.normal;
        if (!std::isfinite(surface.t) || !finite_normal(normal)) continue;  // see nearest_crossing
        RTCRayN_tfar(ray, n, i) = surface.t;
        RTCHitN_Ng_x(hit, n, i) = normal.x;
        RTCHitN_Ng_y(hit, n, i) = normal.y;
        RTCHitN_Ng_z(hit, n, i) = normal.z;
        RTCHitN_u(hit, n, i) = 0.0f;
        RTCHitN_v(hit, n, i) = 0.0f;
        RTCHitN_primID(hit, n, i) = args->primID;
        RTCHitN_geomID(hit, n, i) = args->geomID;
        for (unsigned level = 0; level < RTC_MAX_INSTANCE_LEVEL_COUNT; ++level)
            RTCHitN_instID(hit, n, i, level) = args->context->instID[level];
        csg_records[RTCRayN_id(ray, n, i) & 7u] = {surface.leaf, surface.face, surface.material,
                                                   boundary.medium_inside, boundary.medium_outside};
    }
}

void csg_occluded(const RTCOccludedFunctionNArguments* args) {
    const auto* geometry = static_cast<const CsgGeometry*>(args->geometryUserPtr);
    const CsgTree& tree = geometry->trees[args->primID];
    const std::atomic<bool>* cancel = query_cancel(args->context);
    const unsigned n = args->N;
    for (unsigned i = 0; i < n; ++i) {
        if (args->valid[i] != -1) continue;
        CsgSegmentList list;
        CsgBoundary boundary;
        const bool met = boundary_along_ray(tree, args->ray, n, i, cancel, list, boundary);
        if (is_cancelled(cancel) || (met && std::isfinite(boundary.surface->t)))
            RTCRayN_tfar(args->ray, n, i) = -ray_infinity;  // blocked, or the query was cancelled
    }
}

}  // namespace caustica::user_geometry
