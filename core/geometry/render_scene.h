// The traceable scene: Embree BVH over analytic primitives (user geometry), mesh instances
// (one triangle BVH per mesh file, instanced wherever the mesh is reused) and CSG objects (a
// second user geometry, one primitive per object), plus materials.
#pragma once

#include "core/geometry/csg_tree.h"
#include "core/shading/material.h"
#include "core/geometry/ray.h"
#include "core/render/render_stats.h"
#include "core/scene/scene_flatten.h"

#include <embree3/rtcore.h>

#include <atomic>
#include <memory>
#include <unordered_map>
#include <string>
#include <vector>

namespace caustica {

/// Thrown by RenderScene's constructor when its cancel flag stopped the build.
struct SceneBuildCancelled {};

/// Embree's query context with the flag that stops the query. Every query on a RenderScene's
/// Embree scene passes one (embree_scene() included): its user-geometry callbacks read the flag
/// through the context Embree hands them.
struct RayQueryContext {
    RTCIntersectContext embree;                 ///< first member: the pointer Embree is given
    const std::atomic<bool>* cancel = nullptr;  ///< null: the query always runs to its end

    explicit RayQueryContext(const std::atomic<bool>* cancel_flag = nullptr) : cancel(cancel_flag) {
        rtcInitIntersectContext(&embree);
    }
};

/// Immutable after build; safe to trace from any number of threads.
class RenderScene {
public:
    /// Builds the BVH for a flattened scene. `materials` come from the scene description. When
    /// `cancel` is set during the build, Embree stops it and SceneBuildCancelled is thrown.
    RenderScene(const SceneDesc& desc, const FlatScene& flat, const std::atomic<bool>* cancel = nullptr);
    ~RenderScene();
    RenderScene(const RenderScene&) = delete;
    RenderScene& operator=(const RenderScene&) = delete;

    // Each query takes the render's cancel flag (docs/RELIABILITY.md, "Bounded time"). Once it
    // reads true the query answers a miss (occlusion: blocked), an answer the caller throws away:
    // a query that starts then traces nothing, one under way stops at the next analytic primitive
    // or CSG leaf it tests (Embree's walk through mesh triangles runs to its end). Null (picking,
    // tests): the query always runs to its end.

    /// Nearest hit along the ray within [tmin, tmax].
    bool intersect(const Ray& ray, SurfaceHit& hit, const std::atomic<bool>* cancel = nullptr) const;

    /// Whether anything blocks the ray within [tmin, tmax].
    bool occluded(const Ray& ray, const std::atomic<bool>* cancel = nullptr) const;

    /// Occlusion of up to 8 rays as one packet; `valid[i]` selects lanes, `blocked[i]` the answers.
    void occluded8(const Ray* rays, const int* valid, bool* blocked, const std::atomic<bool>* cancel = nullptr) const;

    /// Traces up to 8 rays as one packet (primary rays); `valid[i]` selects lanes.
    void intersect8(const Ray* rays, const int* valid, SurfaceHit* hits, bool* found,
                    const std::atomic<bool>* cancel = nullptr) const;

    const std::vector<Material>& materials() const { return materials_; }
    /// World bounds of everything finite in the scene.
    glm::vec3 bounds_lo() const { return lo_; }
    glm::vec3 bounds_hi() const { return hi_; }
    /// Ray offset for secondary rays: relative to the scene's size, so a scaled scene renders the same.
    float epsilon() const { return epsilon_; }
    const SceneBuildInfo& info() const { return info_; }
    /// The CSG objects, in the order of FlatScene::csg_objects (empty ones left out).
    const std::vector<CsgTree>& csg_objects() const { return csg_; }

    /// The raw Embree scene, for benchmarks that compare against it (queried with a RayQueryContext).
    RTCScene embree_scene() const { return scene_; }

    /// Per-analytic-primitive data the Embree callbacks read.
    struct AnalyticPrimitive {
        Shape shape;
        glm::mat4 world_to_object;
        glm::mat3 object_to_world;  ///< linear part, for tangents
        glm::mat3 normal_to_world;
        int material;
        bool world_space;  ///< the transform was folded into the shape: intersect without matrices
    };
    /// Per-mesh-instance data for shading.
    struct MeshInstance {
        int mesh;
        glm::mat3 object_to_world;  ///< linear part, for tangents
        glm::mat3 normal_to_world;
        int material;
    };

private:
    /// Fills `hit` from Embree's answer; `lane` is the ray's index in its packet (0 for one ray).
    void fill_hit(const RTCRayHit& rh, int lane, SurfaceHit& hit) const;
    void fill_csg_hit(const RTCRayHit& rh, int lane, SurfaceHit& hit) const;
    /// Object position, uv and tangents of a point of a mesh triangle (barycentrics b1, b2).
    static void fill_mesh_surface(const MeshData& mesh, unsigned triangle, float b1, float b2,
                                  const glm::mat3& object_to_world, SurfaceHit& hit);
    /// The mesh_scenes_ slot of a scene mesh, building its BVH on first use.
    int mesh_slot(const SceneDesc& desc, int mesh, bool robust);
    /// The constructor's work (it releases what was built when this throws).
    void build(const SceneDesc& desc, const FlatScene& flat);
    /// Releases the Embree scenes.
    void release();

    struct AnalyticHolder;
    std::unique_ptr<AnalyticHolder> holder_;  // callback data for the analytic user geometry
    struct CsgHolder;
    std::unique_ptr<CsgHolder> csg_holder_;   // callback data for the CSG user geometry
    std::vector<CsgTree> csg_;
    unsigned csg_geom_id_ = RTC_INVALID_GEOMETRY_ID;
    RTCScene scene_ = nullptr;
    const std::atomic<bool>* cancel_ = nullptr;  ///< during the build only
    std::vector<RTCScene> mesh_scenes_;
    std::vector<std::shared_ptr<const MeshData>> meshes_;
    std::unordered_map<int, int> mesh_slot_;    // SceneDesc mesh index -> mesh_scenes_ index
    std::vector<AnalyticPrimitive> analytic_;
    std::vector<MeshInstance> instances_;       // indexed by top-level geometry id - first_instance_id_
    unsigned analytic_geom_id_ = RTC_INVALID_GEOMETRY_ID;
    unsigned first_instance_id_ = 0;
    std::vector<Material> materials_;
    int default_material_ = 0;
    glm::vec3 lo_{0.0f}, hi_{0.0f};
    float epsilon_ = 1e-4f;
    bool surface_frames_ = false;  // uv and tangents at hits: only when a material has a texture or bump map
    SceneBuildInfo info_;
};

/// The process-wide Embree device (created on first use, errors raised as exceptions).
RTCDevice embree_device();

}  // namespace caustica
