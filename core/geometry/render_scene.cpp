#include "core/geometry/render_scene.h"

#include "core/geometry/render_scene_callbacks.h"
#include "core/geometry/scene_memory.h"
#include "core/scene/source_location.h"
#include "core/util/cancel_flag.h"

#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace caustica {
namespace {

std::string& last_embree_error() {
    static std::string message;
    return message;
}

void on_embree_error(void*, RTCError code, const char* message) {
    last_embree_error() = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
}

/// Embree's build progress callback: false (stop building) once the cancel flag is set.
bool keep_building(void* cancel, double) {
    return !static_cast<const std::atomic<bool>*>(cancel)->load(std::memory_order_relaxed);
}

/// Commits `scene`, stopping when `cancel` is set (SceneBuildCancelled; the caller releases it).
void commit_cancellable(RTCScene scene, const std::atomic<bool>* cancel) {
    if (cancel) rtcSetSceneProgressMonitorFunction(scene, keep_building, const_cast<std::atomic<bool>*>(cancel));
    rtcCommitScene(scene);
    if (cancel && cancel->load()) {
        rtcGetDeviceError(embree_device());  // clears RTC_ERROR_CANCELLED
        throw SceneBuildCancelled{};
    }
}

void check_device(RTCDevice device, const char* what) {
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE)
        throw std::runtime_error(std::string(what) + ": " + last_embree_error());
}

/// `v` scaled to unit length (scaled down first, so that its squared length cannot overflow), or
/// `fallback` when it has no direction.
/// `v` at unit length, or (a normal without direction: a sliver, a cone's apex) the unit vector
/// against the ray, computed only then.
glm::vec3 unit_or_against(const glm::vec3& v, const RTCRay& ray) {
    const float m = std::fmax(std::fabs(v.x), std::fmax(std::fabs(v.y), std::fabs(v.z)));
    if (m > 0.0f && std::isfinite(m)) return glm::normalize(v / m);
    return -glm::normalize(glm::vec3(ray.dir_x, ray.dir_y, ray.dir_z));
}

/// Folds a transform made of a translation and a positive scale into a sphere (uniform scale) or
/// a box, so that the primitive is intersected in world space without matrix products.
bool fold_into_world_space(PlacedPrimitive& p) {
    const glm::dmat4& m = p.object_to_world;
    const glm::dvec3 scale(m[0][0], m[1][1], m[2][2]);
    const bool axis_aligned = m[0][1] == 0.0 && m[0][2] == 0.0 && m[1][0] == 0.0 && m[1][2] == 0.0 &&
                              m[2][0] == 0.0 && m[2][1] == 0.0 && m[0][3] == 0.0 && m[1][3] == 0.0 &&
                              m[2][3] == 0.0 && m[3][3] == 1.0 && scale.x > 0.0 && scale.y > 0.0 && scale.z > 0.0;
    if (p.is_mesh || !axis_aligned) return false;
    const glm::dvec3 offset(m[3]);
    if (p.shape.kind == ShapeKind::box) {
        p.shape.a = glm::vec3(glm::dvec3(p.shape.a) * scale + offset);
        p.shape.b = glm::vec3(glm::dvec3(p.shape.b) * scale + offset);
    } else if (p.shape.kind == ShapeKind::sphere && scale.x == scale.y && scale.y == scale.z) {
        p.shape.a = glm::vec3(glm::dvec3(p.shape.a) * scale + offset);
        p.shape.b = glm::vec3(static_cast<float>(p.shape.b.x * scale.x));
    } else {
        return false;
    }
    p.object_to_world = glm::dmat4(1.0);
    return true;
}

void transformed_bounds(const Shape& shape, const glm::mat4& m, glm::vec3& lo, glm::vec3& hi) {
    glm::vec3 olo, ohi;
    shape_bounds(shape, olo, ohi);
    transformed_box(olo, ohi, m, lo, hi);
}

/// Barycentric coordinates (of v1 and v2) of a point in the plane of a triangle.
glm::vec2 barycentric(const glm::vec3& p, const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2) {
    const glm::vec3 e1 = v1 - v0, e2 = v2 - v0, q = p - v0;
    const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const float q1 = glm::dot(q, e1), q2 = glm::dot(q, e2);
    const float det = d11 * d22 - d12 * d12;
    if (!(std::fabs(det) > 0.0f)) return {0.0f, 0.0f};
    return {(d22 * q1 - d12 * q2) / det, (d11 * q2 - d12 * q1) / det};
}

RTCRay to_embree(const Ray& ray) {
    RTCRay r{};
    r.org_x = ray.origin.x, r.org_y = ray.origin.y, r.org_z = ray.origin.z;
    r.dir_x = ray.direction.x, r.dir_y = ray.direction.y, r.dir_z = ray.direction.z;
    r.tnear = ray.tmin;
    r.tfar = ray.tmax;
    r.mask = 0xffffffffu;
    r.flags = 0;
    r.time = 0.0f;
    return r;
}

}  // namespace

RTCDevice embree_device() {
    static std::once_flag once;
    static RTCDevice device = nullptr;
    std::call_once(once, [] {
        device = rtcNewDevice(nullptr);
        if (!device) throw std::runtime_error("cannot create the Embree device");
        rtcSetDeviceErrorFunction(device, on_embree_error, nullptr);
    });
    return device;
}

// The user geometries' callback data, owned by the scene.
struct RenderScene::AnalyticHolder {
    user_geometry::AnalyticGeometry geometry;
    std::vector<glm::vec3> lo, hi;
};
struct RenderScene::CsgHolder {
    user_geometry::CsgGeometry geometry;
};

int RenderScene::mesh_slot(const SceneDesc& desc, int mesh_index, bool robust) {
    auto [it, inserted] = mesh_slot_.try_emplace(mesh_index, static_cast<int>(mesh_scenes_.size()));
    if (!inserted) return it->second;
    RTCDevice device = embree_device();
    const MeshData& mesh = *desc.meshes.at(mesh_index);
    RTCScene mesh_scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(mesh_scene, RTC_BUILD_QUALITY_HIGH);
    // CSG counts a mesh's crossings along a line: ask Embree for its watertight intersection.
    if (robust) rtcSetSceneFlags(mesh_scene, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(float) * 3, mesh.positions.size()));
    std::memcpy(vertices, mesh.positions.data(), sizeof(float) * 3 * mesh.positions.size());
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, sizeof(unsigned) * 3, mesh.triangles.size()));
    std::memcpy(indices, mesh.triangles.data(), sizeof(unsigned) * 3 * mesh.triangles.size());
    rtcCommitGeometry(g);
    rtcAttachGeometry(mesh_scene, g);
    rtcReleaseGeometry(g);
    try {
        commit_cancellable(mesh_scene, cancel_);
    } catch (...) {
        rtcReleaseScene(mesh_scene);
        throw;
    }
    check_device(device, "building a mesh");
    mesh_scenes_.push_back(mesh_scene);
    meshes_.push_back(desc.meshes.at(mesh_index));
    info_.triangles_stored += mesh.triangles.size();
    return it->second;
}

RenderScene::RenderScene(const SceneDesc& desc, const FlatScene& flat, const std::atomic<bool>* cancel)
    : cancel_(cancel) {
    try {
        build(desc, flat);
    } catch (...) {
        release();  // the destructor does not run for a constructor that throws
        throw;
    }
    cancel_ = nullptr;
}

void RenderScene::build(const SceneDesc& desc, const FlatScene& flat) {
    RTCDevice device = embree_device();
    info_.estimated_bytes = total_bytes(scene_memory_charges(desc, flat));  // the photon maps get the rest
    for (const MaterialDesc& m : desc.materials) materials_.push_back(Material::from_desc(m));
    default_material_ = static_cast<int>(materials_.size());
    for (const MaterialDesc& m : desc.materials) surface_frames_ |= m.texture >= 0 || m.bumpmap >= 0;
    Material grey;
    grey.kd = glm::vec3(0.6f);
    materials_.push_back(grey);

    scene_ = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);

    auto holder = std::make_unique<AnalyticHolder>();
    std::unordered_set<int> csg_meshes;  // meshes that CSG traces through
    for (const FlatCsgObject& object : flat.csg_objects)
        for (const PlacedPrimitive& leaf : object.leaves)
            if (leaf.is_mesh) csg_meshes.insert(leaf.mesh);
    struct PendingInstance {
        int slot;
        glm::mat4 transform;
        int material;
    };
    std::vector<PendingInstance> pending;
    for (PlacedPrimitive p : flat.primitives) {
        const bool world_space = fold_into_world_space(p);
        const glm::mat4 to_world = glm::mat4(p.object_to_world);
        const glm::mat3 normal_to_world = glm::mat3(glm::transpose(glm::inverse(p.object_to_world)));
        const int material = p.material >= 0 ? p.material : default_material_;
        if (!p.is_mesh) {
            analytic_.push_back({p.shape, glm::mat4(glm::inverse(p.object_to_world)), glm::mat3(to_world), normal_to_world,
                                 material, world_space});
            glm::vec3 lo, hi;
            transformed_bounds(p.shape, to_world, lo, hi);
            holder->lo.push_back(lo);
            holder->hi.push_back(hi);
            continue;
        }
        const int slot = mesh_slot(desc, p.mesh, csg_meshes.count(p.mesh) > 0);
        pending.push_back({slot, to_world, material});
        info_.triangles_instanced += meshes_[slot]->triangles.size();
        instances_.push_back({slot, glm::mat3(to_world), normal_to_world, material});
    }
    for (const FlatCsgObject& object : flat.csg_objects) {
        CsgTree tree(object, desc, default_material_,
                     [&](int mesh) { return mesh_scenes_[mesh_slot(desc, mesh, true)]; });
        info_.csg_leaves += tree.leaf_count();
        if (!tree.empty()) csg_.push_back(std::move(tree));  // an empty root box is never hit
    }

    if (!analytic_.empty()) {
        holder->geometry = {analytic_.data(), holder->lo.data(), holder->hi.data(),
                            static_cast<unsigned>(analytic_.size()), !flat.bounding_volumes};
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(g, flat.bounding_volumes ? static_cast<unsigned>(analytic_.size()) : 1u);
        rtcSetGeometryUserData(g, &holder->geometry);
        rtcSetGeometryBoundsFunction(g, user_geometry::analytic_bounds, nullptr);
        rtcSetGeometryIntersectFunction(g, user_geometry::analytic_intersect);
        rtcSetGeometryOccludedFunction(g, user_geometry::analytic_occluded);
        rtcCommitGeometry(g);
        analytic_geom_id_ = rtcAttachGeometry(scene_, g);
        rtcReleaseGeometry(g);
    }
    first_instance_id_ = analytic_.empty() ? 0u : 1u;
    for (std::size_t i = 0; i < pending.size(); ++i) {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(g, mesh_scenes_[pending[i].slot]);
        rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, glm::value_ptr(pending[i].transform));
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(scene_, g, first_instance_id_ + static_cast<unsigned>(i));
        rtcReleaseGeometry(g);
    }
    auto csg_holder = std::make_unique<CsgHolder>();
    if (!csg_.empty()) {
        csg_holder->geometry = {csg_.data()};
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(csg_.size()));
        rtcSetGeometryUserData(g, &csg_holder->geometry);
        rtcSetGeometryBoundsFunction(g, user_geometry::csg_bounds, nullptr);
        rtcSetGeometryIntersectFunction(g, user_geometry::csg_intersect);
        rtcSetGeometryOccludedFunction(g, user_geometry::csg_occluded);
        rtcCommitGeometry(g);
        csg_geom_id_ = first_instance_id_ + static_cast<unsigned>(pending.size());
        rtcAttachGeometryByID(scene_, g, csg_geom_id_);
        rtcReleaseGeometry(g);
    }
    commit_cancellable(scene_, cancel_);
    check_device(device, "building the scene");
    holder_ = std::move(holder);
    csg_holder_ = std::move(csg_holder);

    info_.analytic_primitives = analytic_.size();
    info_.mesh_instances = instances_.size();
    info_.unique_meshes = mesh_scenes_.size();
    info_.csg_objects = csg_.size();

    RTCBounds b;
    rtcGetSceneBounds(scene_, &b);
    if ((flat.primitives.empty() && csg_.empty()) || !(b.lower_x <= b.upper_x)) {
        lo_ = hi_ = glm::vec3(0.0f);
    } else {
        lo_ = {b.lower_x, b.lower_y, b.lower_z};
        hi_ = {b.upper_x, b.upper_y, b.upper_z};
    }
    const float diagonal = glm::length(hi_ - lo_);
    epsilon_ = (std::isfinite(diagonal) && diagonal > 0.0f) ? 1e-5f * diagonal : 1e-4f;
    // CSG treats surfaces closer than the ray offset as touching (the original's CSG epsilon).
    for (CsgTree& tree : csg_) {
        tree.set_epsilon(epsilon_);
        tree.set_bounding_boxes(flat.csg_bounding_boxes);
    }
}

RenderScene::~RenderScene() { release(); }

void RenderScene::release() {
    if (scene_) rtcReleaseScene(scene_);
    scene_ = nullptr;
    for (RTCScene s : mesh_scenes_) rtcReleaseScene(s);
    mesh_scenes_.clear();
}

void RenderScene::fill_mesh_surface(const MeshData& mesh, unsigned triangle, float b1, float b2,
                                    const glm::mat3& object_to_world, SurfaceHit& hit) {
    const glm::uvec3 tri = mesh.triangles[triangle];
    const glm::vec3 v0 = mesh.positions[tri.x], v1 = mesh.positions[tri.y], v2 = mesh.positions[tri.z];
    hit.face = 0;
    hit.shape_kind = -1;
    hit.object_position = (1.0f - b1 - b2) * v0 + b1 * v1 + b2 * v2;
    glm::vec2 t0(0.0f, 0.0f), t1(1.0f, 0.0f), t2(0.0f, 1.0f);
    if (!mesh.texcoords.empty()) {
        const std::size_t c = static_cast<std::size_t>(triangle) * 3;
        t0 = mesh.texcoords[c], t1 = mesh.texcoords[c + 1], t2 = mesh.texcoords[c + 2];
    }
    hit.uv = (1.0f - b1 - b2) * t0 + b1 * t1 + b2 * t2;
    // Tangents from the triangle's texture mapping: solve [e1 e2] = [dpdu dpdv] [du dv].
    const glm::vec2 duv1 = t1 - t0, duv2 = t2 - t0;
    const float det = duv1.x * duv2.y - duv1.y * duv2.x;
    const glm::vec3 e1 = v1 - v0, e2 = v2 - v0;
    glm::vec3 dpdu(0.0f), dpdv(0.0f);
    if (std::fabs(det) > 1e-12f) {
        dpdu = (duv2.y * e1 - duv1.y * e2) / det;
        dpdv = (-duv2.x * e1 + duv1.x * e2) / det;
    }
    hit.dpdu = object_to_world * dpdu;
    hit.dpdv = object_to_world * dpdv;
}

void RenderScene::fill_hit(const RTCRayHit& rh, int lane, SurfaceHit& hit) const {
    hit.t = rh.ray.tfar;
    hit.position = glm::vec3(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z) +
                   hit.t * glm::vec3(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
    if (rh.hit.geomID == csg_geom_id_) {
        fill_csg_hit(rh, lane, hit);
        return;
    }
    const unsigned instance = rh.hit.instID[0];
    if (instance == RTC_INVALID_GEOMETRY_ID) {
        const AnalyticPrimitive& prim = analytic_[rh.hit.primID];
        // A cone's apex has no normal: face the ray there (as for slivers below).
        hit.normal = unit_or_against(glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z), rh.ray);
        hit.face = static_cast<int>(rh.hit.u);
        hit.material = prim.material;
        hit.shape_kind = static_cast<int>(prim.shape.kind);
        if (surface_frames_) {  // only textures and bump maps need these: skip the trigonometry
            hit.object_position = glm::vec3(prim.world_to_object * glm::vec4(hit.position, 1.0f));
            hit.uv = shape_uv(prim.shape, hit.object_position, hit.face);
            glm::vec3 dpdu, dpdv;
            shape_tangents(prim.shape, hit.object_position, hit.face, dpdu, dpdv);
            // The bump tangents go through the normal matrix (docs/TEXTURES.md, "Bump maps").
            hit.dpdu = prim.normal_to_world * dpdu;
            hit.dpdv = prim.normal_to_world * dpdv;
        }
    } else {
        const MeshInstance& inst = instances_[instance - first_instance_id_];
        const MeshData& mesh = *meshes_[inst.mesh];
        const glm::uvec3 tri = mesh.triangles[rh.hit.primID];
        const glm::vec3 v0 = mesh.positions[tri.x], v1 = mesh.positions[tri.y], v2 = mesh.positions[tri.z];
        // Our own winding rule (counter-clockwise = outward, as OBJ files are written), not Embree's.
        const glm::vec3 n = inst.normal_to_world * glm::cross(v1 - v0, v2 - v0);
        // A sliver whose cross product underflows has no direction: face the ray instead.
        hit.normal = unit_or_against(n, rh.ray);
        hit.material = inst.material;
        if (surface_frames_) fill_mesh_surface(mesh, rh.hit.primID, rh.hit.u, rh.hit.v, inst.object_to_world, hit);
    }
    hit.medium_inside = hit.material;
    hit.medium_outside = -1;
    hit.in_csg = false;
}

void RenderScene::fill_csg_hit(const RTCRayHit& rh, int lane, SurfaceHit& hit) const {
    const CsgTree& tree = csg_[rh.hit.primID];
    const user_geometry::CsgHitRecord& record = user_geometry::csg_hit_record(lane);
    const CsgLeaf& leaf = tree.leaf(record.leaf);
    // The normal of the surface the CSG chose, already oriented from its inside medium to its outside.
    hit.normal = unit_or_against(glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z), rh.ray);
    hit.material = record.material;
    hit.medium_inside = record.medium_inside;
    hit.medium_outside = record.medium_outside;
    hit.in_csg = true;
    hit.face = record.face;
    hit.shape_kind = leaf.is_mesh ? -1 : static_cast<int>(leaf.shape.kind);
    if (!surface_frames_) return;
    const glm::vec3 object_position = glm::vec3(leaf.world_to_object * glm::vec4(hit.position, 1.0f));
    if (leaf.is_mesh) {
        const unsigned triangle = static_cast<unsigned>(record.face);
        const glm::uvec3 tri = leaf.mesh->triangles[triangle];
        const glm::vec2 b = barycentric(object_position, leaf.mesh->positions[tri.x], leaf.mesh->positions[tri.y],
                                        leaf.mesh->positions[tri.z]);
        fill_mesh_surface(*leaf.mesh, triangle, b.x, b.y, leaf.object_to_world, hit);
        return;
    }
    hit.object_position = object_position;
    hit.uv = shape_uv(leaf.shape, object_position, hit.face);
    glm::vec3 dpdu, dpdv;
    shape_tangents(leaf.shape, object_position, hit.face, dpdu, dpdv);
    hit.dpdu = leaf.normal_to_world * dpdu;  // through the normal matrix
    hit.dpdv = leaf.normal_to_world * dpdv;
}

// A query the cancel flag stopped (before it started or while it ran) answers a miss, or blocked:
// what Embree left in the ray is not an answer (a callback ended it with a negative tfar).

bool RenderScene::intersect(const Ray& ray, SurfaceHit& hit, const std::atomic<bool>* cancel) const {
    if (is_cancelled(cancel) || !embree_traceable(ray)) return false;  // numerical accidents: a miss
    RayQueryContext context(cancel);
    RTCRayHit rh;
    rh.ray = to_embree(ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context.embree, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || is_cancelled(cancel)) return false;
    fill_hit(rh, 0, hit);
    return true;
}

bool RenderScene::occluded(const Ray& ray, const std::atomic<bool>* cancel) const {
    if (is_cancelled(cancel) || !embree_traceable(ray)) return true;  // numerical accidents: no light
    RayQueryContext context(cancel);
    RTCRay r = to_embree(ray);
    rtcOccluded1(scene_, &context.embree, &r);
    return r.tfar < 0.0f || is_cancelled(cancel);
}

void RenderScene::occluded8(const Ray* rays, const int* valid, bool* blocked, const std::atomic<bool>* cancel) const {
    if (is_cancelled(cancel)) {
        for (int i = 0; i < 8; ++i) blocked[i] = valid[i] != 0;
        return;
    }
    RayQueryContext context(cancel);
    alignas(32) RTCRay8 packet;
    alignas(32) int mask[8];
    bool untraceable[8];
    for (int i = 0; i < 8; ++i) {
        untraceable[i] = valid[i] && !embree_traceable(rays[i]);
        mask[i] = valid[i] && !untraceable[i] ? -1 : 0;
        const Ray& r = mask[i] ? rays[i] : Ray{};
        packet.org_x[i] = r.origin.x, packet.org_y[i] = r.origin.y, packet.org_z[i] = r.origin.z;
        packet.dir_x[i] = r.direction.x, packet.dir_y[i] = r.direction.y, packet.dir_z[i] = r.direction.z;
        packet.tnear[i] = r.tmin;
        packet.tfar[i] = r.tmax;
        packet.mask[i] = 0xffffffffu;
        packet.flags[i] = 0;
        packet.time[i] = 0.0f;
        packet.id[i] = static_cast<unsigned>(i);
    }
    rtcOccluded8(mask, scene_, &context.embree, &packet);
    const bool stopped = is_cancelled(cancel);
    for (int i = 0; i < 8; ++i) blocked[i] = valid[i] && (untraceable[i] || stopped || packet.tfar[i] < 0.0f);
}

void RenderScene::intersect8(const Ray* rays, const int* valid, SurfaceHit* hits, bool* found,
                             const std::atomic<bool>* cancel) const {
    if (is_cancelled(cancel)) {
        for (int i = 0; i < 8; ++i) found[i] = false;
        return;
    }
    RayQueryContext context(cancel);
    context.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(32) RTCRayHit8 packet;
    alignas(32) int mask[8];
    for (int i = 0; i < 8; ++i) {
        mask[i] = valid[i] && embree_traceable(rays[i]) ? -1 : 0;
        const Ray& r = mask[i] ? rays[i] : Ray{};
        packet.ray.org_x[i] = r.origin.x, packet.ray.org_y[i] = r.origin.y, packet.ray.org_z[i] = r.origin.z;
        packet.ray.dir_x[i] = r.direction.x, packet.ray.dir_y[i] = r.direction.y, packet.ray.dir_z[i] = r.direction.z;
        packet.ray.tnear[i] = r.tmin;
        packet.ray.tfar[i] = r.tmax;
        packet.ray.mask[i] = 0xffffffffu;
        packet.ray.flags[i] = 0;
        packet.ray.time[i] = 0.0f;
        packet.ray.id[i] = static_cast<unsigned>(i);
        packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect8(mask, scene_, &context.embree, &packet);
    const bool stopped = is_cancelled(cancel);
    for (int i = 0; i < 8; ++i) {
        found[i] = !stopped && mask[i] && packet.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
        if (!found[i]) continue;
        RTCRayHit one;
        one.ray.org_x = packet.ray.org_x[i], one.ray.org_y = packet.ray.org_y[i], one.ray.org_z = packet.ray.org_z[i];
        one.ray.dir_x = packet.ray.dir_x[i], one.ray.dir_y = packet.ray.dir_y[i], one.ray.dir_z = packet.ray.dir_z[i];
        one.ray.tfar = packet.ray.tfar[i];
        one.hit.Ng_x = packet.hit.Ng_x[i], one.hit.Ng_y = packet.hit.Ng_y[i], one.hit.Ng_z = packet.hit.Ng_z[i];
        one.hit.u = packet.hit.u[i], one.hit.v = packet.hit.v[i];
        one.hit.primID = packet.hit.primID[i];
        one.hit.geomID = packet.hit.geomID[i];
        one.hit.instID[0] = packet.hit.instID[0][i];
        fill_hit(one, i, hits[i]);
    }
}

}  // namespace caustica
