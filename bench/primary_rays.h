// Embree queries of a camera's primary rays, nothing else: the ray-casting rate the benchmarks
// hold the renderer against (bench_render, trade --pass-time).
#pragma once

#include "core/geometry/render_scene.h"
#include "core/scene/camera.h"

#include <embree3/rtcore.h>

namespace caustica::bench {

/// Fills `packet` with the primary rays through the centres of pixels x .. x + 7 of row y; lanes at
/// or past `x_end` are invalid.
inline void primary_packet(const Camera& camera, int x, int y, int x_end, RTCRayHit8& packet, int (&valid)[8]) {
    for (int i = 0; i < 8; ++i) {
        valid[i] = x + i < x_end ? -1 : 0;
        const Ray r = camera.generate(float(x + i) + 0.5f, float(y) + 0.5f);
        packet.ray.org_x[i] = r.origin.x, packet.ray.org_y[i] = r.origin.y, packet.ray.org_z[i] = r.origin.z;
        packet.ray.dir_x[i] = r.direction.x, packet.ray.dir_y[i] = r.direction.y, packet.ray.dir_z[i] = r.direction.z;
        packet.ray.tnear[i] = 0.0f;
        packet.ray.tfar[i] = ray_infinity;
        packet.ray.mask[i] = 0xffffffffu;
        packet.ray.flags[i] = 0;
        packet.ray.time[i] = 0.0f;
        packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    }
}

/// Traces pixels x .. x + 7 of row y (those before `x_end`) as one coherent 8-wide packet; how many hit.
inline unsigned trace_primary_packet(RTCScene scene, RayQueryContext& context, const Camera& camera, int x, int y,
                                     int x_end) {
    alignas(32) RTCRayHit8 packet;
    alignas(32) int valid[8];
    primary_packet(camera, x, y, x_end, packet, valid);
    rtcInitIntersectContext(&context.embree);
    context.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    rtcIntersect8(valid, scene, &context.embree, &packet);
    unsigned hits = 0;
    for (int i = 0; i < 8; ++i) hits += packet.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
    return hits;
}

/// Traces the primary ray through the centre of pixel (x, y) alone; 1 if it hits.
inline unsigned trace_primary_ray(RTCScene scene, RayQueryContext& context, const Camera& camera, int x, int y) {
    const Ray r = camera.generate(float(x) + 0.5f, float(y) + 0.5f);
    RTCRayHit rh;
    rh.ray.org_x = r.origin.x, rh.ray.org_y = r.origin.y, rh.ray.org_z = r.origin.z;
    rh.ray.dir_x = r.direction.x, rh.ray.dir_y = r.direction.y, rh.ray.dir_z = r.direction.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = ray_infinity;
    rh.ray.mask = 0xffffffffu;
    rh.ray.flags = 0;
    rh.ray.time = 0.0f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcInitIntersectContext(&context.embree);
    rtcIntersect1(scene, &context.embree, &rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? 1u : 0u;
}

}  // namespace caustica::bench
