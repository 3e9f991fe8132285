// The traceable scene: Embree BVH over analytic primitives (user geometry) and mesh instances
// (one triangle BVH per mesh file, instanced wherever the mesh is reused), plus materials.
#pragma once

#include "core/material.h"
#include "core/ray.h"
#include "core/scene_flatten.h"

#include <embree3/rtcore.h>

#include <memory>
#include <string>
#include <vector>

namespace caustica {

/// Counts of what a build produced, for -S.
struct SceneBuildInfo {
    std::size_t analytic_primitives = 0;
    std::size_t mesh_instances = 0;
    std::size_t unique_meshes = 0;
    std::size_t triangles_stored = 0;     ///< triangles held once per mesh file
    std::size_t triangles_instanced = 0;  ///< triangles as seen in the world
};

/// Immutable after build; safe to trace from any number of threads.
class RenderScene {
public:
    /// Builds the BVH for a flattened scene. `materials` come from the scene description.
    RenderScene(const SceneDesc& desc, const FlatScene& flat);
    ~RenderScene();
    RenderScene(const RenderScene&) = delete;
    RenderScene& operator=(const RenderScene&) = delete;

    /// Nearest hit along the ray within [tmin, tmax].
    bool intersect(const Ray& ray, SurfaceHit& hit) const;

    /// Whether anything blocks the ray within [tmin, tmax].
    bool occluded(const Ray& ray) const;

    /// Traces up to 8 rays as one packet (primary rays); `valid[i]` selects lanes.
    void intersect8(const Ray* rays, const int* valid, SurfaceHit* hits, bool* found) const;

    const std::vector<Material>& materials() const { return materials_; }
    /// World bounds of everything finite in the scene.
    glm::vec3 bounds_lo() const { return lo_; }
    glm::vec3 bounds_hi() const { return hi_; }
    /// Ray offset for secondary rays: relative to the scene's size, so a scaled scene renders the same.
    float epsilon() const { return epsilon_; }
    const SceneBuildInfo& info() const { return info_; }

    /// The raw Embree scene, for benchmarks that compare against it.
    RTCScene embree_scene() const { return scene_; }

    /// Per-analytic-primitive data the Embree callbacks read.
    struct AnalyticPrimitive {
        Shape shape;
        glm::mat4 world_to_object;
        glm::mat3 object_to_world;  ///< linear part, for tangents
        glm::mat3 normal_to_world;
        int material;
    };
    /// Per-mesh-instance data for shading.
    struct MeshInstance {
        int mesh;
        glm::mat3 object_to_world;  ///< linear part, for tangents
        glm::mat3 normal_to_world;
        int material;
    };

private:
    void fill_hit(const RTCRayHit& rh, SurfaceHit& hit) const;

    struct AnalyticHolder;
    std::unique_ptr<AnalyticHolder> holder_;  // callback data for the analytic user geometry
    RTCScene scene_ = nullptr;
    std::vector<RTCScene> mesh_scenes_;
    std::vector<std::shared_ptr<const MeshData>> meshes_;
    std::vector<AnalyticPrimitive> analytic_;
    std::vector<MeshInstance> instances_;       // indexed by top-level geometry id - first_instance_id_
    unsigned analytic_geom_id_ = RTC_INVALID_GEOMETRY_ID;
    unsigned first_instance_id_ = 0;
    std::vector<Material> materials_;
    int default_material_ = 0;
    glm::vec3 lo_{0.0f}, hi_{0.0f};
    float epsilon_ = 1e-4f;
    SceneBuildInfo info_;
};

/// The process-wide Embree device (created on first use, errors raised as exceptions).
RTCDevice embree_device();

}  // namespace caustica
