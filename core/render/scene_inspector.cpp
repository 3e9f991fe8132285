#include "core/render/scene_inspector.h"

#include "core/geometry/render_scene.h"
#include "core/geometry/shapes.h"
#include "core/integrators/registry.h"
#include "core/photons/caustic_stage.h"
#include "core/scene/scene_flatten.h"
#include "core/shading/material.h"
#include "core/util/printable_text.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace caustica {

/// For inspect(): which node made each primitive, with world bounds to tell primitives of the same
/// material apart, and the materials' script lines.
struct SceneInspector::Index {
    struct Primitive {
        int material = -1;  // RenderScene material index (the default material last)
        int node = -1;
        bool is_mesh = false;
        Shape shape;
        glm::mat4 world_to_object{1.0f};
        glm::vec3 lo{0.0f}, hi{0.0f};  // world bounds
    };
    struct CsgObject {
        int node = -1;
        glm::vec3 lo{0.0f}, hi{0.0f};
    };
    std::vector<Primitive> primitives;
    std::vector<CsgObject> csg;
    std::vector<std::string> node_names, node_wheres, material_wheres;
    std::vector<Material> materials;  // as RenderScene::materials()
};

namespace {

// World bounds of a placed primitive (mesh bounds are computed once per mesh).
void placed_bounds(const SceneDesc& desc, const PlacedPrimitive& p, std::vector<std::pair<glm::vec3, glm::vec3>>& mesh_boxes,
                   glm::vec3& lo, glm::vec3& hi) {
    glm::vec3 olo(0.0f), ohi(0.0f);
    if (p.is_mesh && p.mesh >= 0 && p.mesh < static_cast<int>(desc.meshes.size()) && desc.meshes[p.mesh]) {
        auto& box = mesh_boxes[static_cast<std::size_t>(p.mesh)];
        if (box.first.x > box.second.x) {
            for (const glm::vec3& v : desc.meshes[p.mesh]->positions) {
                box.first = glm::min(box.first, v);
                box.second = glm::max(box.second, v);
            }
        }
        olo = box.first;
        ohi = box.second;
    } else if (!p.is_mesh) {
        shape_bounds(p.shape, olo, ohi);
    }
    lo = glm::vec3(std::numeric_limits<float>::max());
    hi = -lo;
    const glm::mat4 m(p.object_to_world);
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner((c & 1) ? ohi.x : olo.x, (c & 2) ? ohi.y : olo.y, (c & 4) ? ohi.z : olo.z);
        const glm::vec3 w(m * glm::vec4(corner, 1.0f));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
}

bool inside(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi, float slack) {
    return glm::all(glm::greaterThanEqual(p, lo - slack)) && glm::all(glm::lessThanEqual(p, hi + slack));
}

}  // namespace

std::shared_ptr<const SceneInspector::Index> SceneInspector::make_index(const RenderJob& job) {
    FlatScene flat;
    try {
        flat = flatten_scene(job);  // validated when the scene was built: this does not throw
    } catch (const std::exception&) {
        return nullptr;
    }
    const SceneDesc& desc = *job.scene;
    auto index = std::make_shared<Index>();
    const float inf = std::numeric_limits<float>::max();
    std::vector<std::pair<glm::vec3, glm::vec3>> mesh_boxes(desc.meshes.size(), {glm::vec3(inf), glm::vec3(-inf)});
    const int default_material = static_cast<int>(desc.materials.size());
    for (const PlacedPrimitive& p : flat.primitives) {
        Index::Primitive q;
        q.material = p.material >= 0 ? p.material : default_material;
        q.node = p.node;
        q.is_mesh = p.is_mesh;
        q.shape = p.shape;
        q.world_to_object = glm::mat4(glm::inverse(p.object_to_world));
        placed_bounds(desc, p, mesh_boxes, q.lo, q.hi);
        index->primitives.push_back(q);
    }
    for (const FlatCsgObject& object : flat.csg_objects) {
        Index::CsgObject c{object.node, glm::vec3(inf), glm::vec3(-inf)};
        for (const PlacedPrimitive& leaf : object.leaves) {
            glm::vec3 lo, hi;
            placed_bounds(desc, leaf, mesh_boxes, lo, hi);
            c.lo = glm::min(c.lo, lo);
            c.hi = glm::max(c.hi, hi);
        }
        index->csg.push_back(c);
    }
    // Names and file names are the script's text, kept as they are shown (docs/RELIABILITY.md,
    // "Script text reaches the user bounded and visible").
    for (const NodeDesc& n : desc.nodes) {
        index->node_names.push_back(printable_text(n.name, script_text_limit));
        index->node_wheres.push_back(printable_text(n.where.str()));
    }
    for (const MaterialDesc& m : desc.materials) {
        index->material_wheres.push_back(printable_text(m.where.str()));
        index->materials.push_back(Material::from_desc(m));
    }
    return index;
}

std::optional<SurfaceInspection> SceneInspector::inspect(const std::shared_ptr<const RenderScene>& scene,
                                                        const std::shared_ptr<const RenderJob>& job,
                                                        const std::shared_ptr<const CausticStage>& stage,
                                                        const Ray& ray, const Options& options) const {
    SurfaceHit hit;
    if (!scene || !scene->intersect(ray, hit)) return std::nullopt;
    // The node index is built on the first inspection of a scene (flattening it again), so that
    // renders that never inspect pay nothing for it.
    std::shared_ptr<const Index> index;
    {
        std::lock_guard lock(mutex_);
        if (index_job_ != job) {
            index_ = job && job->scene ? make_index(*job) : nullptr;
            index_job_ = job;
        }
        index = index_;
    }
    SurfaceInspection out;
    out.point = hit.position;
    out.distance = hit.t;
    const std::vector<Material>& materials = scene->materials();
    if (hit.material >= 0 && hit.material < static_cast<int>(materials.size())) {
        const Material& m = materials[static_cast<std::size_t>(hit.material)];
        out.kd = m.kd;
        out.ks = m.ks;
        out.reflective = m.reflective;
        out.transparent = m.transparent;
    }
    if (index) {
        const bool scripted = hit.material >= 0 && hit.material < static_cast<int>(index->material_wheres.size());
        out.material = scripted ? hit.material : -1;
        if (scripted) out.material_where = index->material_wheres[static_cast<std::size_t>(hit.material)];
        // The node: among the primitives of the hit's material, an analytic shape the ray crosses
        // at the hit's distance, else a mesh or CSG object whose bounds hold the point.
        const float slack = 1e-3f * (1.0f + glm::length(hit.position));
        int node = -1;
        float best = std::numeric_limits<float>::max();
        if (hit.in_csg) {
            for (const Index::CsgObject& c : index->csg)
                if (inside(hit.position, c.lo, c.hi, slack)) {
                    node = c.node;
                    break;
                }
        } else {
            for (const Index::Primitive& p : index->primitives) {
                if (p.material != hit.material || !inside(hit.position, p.lo, p.hi, slack)) continue;
                float miss = 1e30f;  // a mesh whose bounds hold the point: any analytic crossing wins
                if (!p.is_mesh) {
                    const glm::vec3 o(p.world_to_object * glm::vec4(ray.origin, 1.0f));
                    const glm::vec3 d(p.world_to_object * glm::vec4(ray.direction, 0.0f));
                    ShapeInterval interval;
                    if (!intersect_shape_interval(p.shape, o, d, interval)) continue;
                    miss = std::min(std::abs(interval.entry.t - hit.t), std::abs(interval.exit.t - hit.t));
                    if (miss > slack * (1.0f + hit.t)) continue;
                }
                if (miss < best) {
                    best = miss;
                    node = p.node;
                }
            }
        }
        if (node >= 0 && node < static_cast<int>(index->node_names.size())) {
            out.object = index->node_names[static_cast<std::size_t>(node)];
            out.object_where = index->node_wheres[static_cast<std::size_t>(node)];
        }
    }
    // The caustic gather as the integrator does it, at the shading normal facing the ray.
    const glm::vec3 n = glm::dot(hit.normal, ray.direction) > 0.0f ? -hit.normal : hit.normal;
    if (!stage || !stage->map || stage->map->size() == 0) return out;
    // N is validated: at most a million.
    std::vector<Neighbour> scratch(static_cast<std::size_t>(std::max(options.caustic_num_neighbours, 1)));
    out.map_photons = stage->map->size();
    out.caustic =
        integrator_entry(options.integrator).caustic_readout(*stage->map, hit.position, n, out.kd, options, scratch.data());
    return out;
}

}  // namespace caustica
