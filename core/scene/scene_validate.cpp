#include "core/scene/scene_validate.h"

#include "core/integrators/registry.h"
#include "core/photons/caustic_stage.h"
#include "core/geometry/shapes.h"
#include "core/scene/source_location.h"

#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace caustica {
namespace {

constexpr double pi = 3.14159265358979323846;

std::string number(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::string vector_text(const glm::dvec3& v) { return "(" + number(v.x) + ", " + number(v.y) + ", " + number(v.z) + ")"; }

const char* transform_call(TransformOp::Kind kind) {
    switch (kind) {
        case TransformOp::Kind::translate: return "node:translate";
        case TransformOp::Kind::scale: return "node:scale";
        case TransformOp::Kind::rotate: return "node:rotate";
    }
    return "node:translate";
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double max_abs(const glm::dvec3& v) { return std::fmax(std::fabs(v.x), std::fmax(std::fabs(v.y), std::fabs(v.z))); }

/// A point (or translation) within +-max_coordinate on every axis.
void check_coordinates(const SourceLocation& where, const std::string& call, const std::string& what,
                       const glm::dvec3& p, double extra = 0.0) {
    if (finite(p) && max_abs(p) + extra <= max_coordinate) return;
    throw InputError(where, call + ": " + what + " " + vector_text(p) +
                                " is beyond the renderer's range: every coordinate must be within +-" +
                                number(max_coordinate) + " (single-precision rays)");
}

/// A colour-like value: finite, not negative, at most max_colour_value per component.
void check_colour(const SourceLocation& where, const std::string& call, const std::string& what,
                  const glm::dvec3& c) {
    for (int i = 0; i < 3; ++i) {
        if (std::isfinite(c[i]) && c[i] >= 0.0 && c[i] <= max_colour_value) continue;
        throw InputError(where, call + ": " + what + "[" + std::to_string(i + 1) + "] = " + number(c[i]) +
                                    " is outside the renderer's range [0, " + number(max_colour_value) +
                                    "] for colours");
    }
}

/// A unit-able direction (any finite, non-zero length), scaled first so that its length cannot
/// overflow or underflow.
bool usable_direction(const glm::dvec3& v, glm::dvec3& unit) {
    const double m = max_abs(v);
    if (!finite(v) || !(m > 0.0)) return false;
    unit = glm::normalize(v / m);
    return true;
}

void check_camera(const RenderJob& job) {
    const std::string call = "gr.render";
    const CameraDesc& c = job.camera;
    check_coordinates(job.where, call, "eye", c.eye);
    glm::dvec3 view, up;
    if (!usable_direction(c.view, view))
        throw InputError(job.where, call + ": view " + vector_text(c.view) + " is not a usable direction");
    if (!usable_direction(c.up, up))
        throw InputError(job.where, call + ": up " + vector_text(c.up) + " is not a usable direction");
    if (!(glm::length(glm::cross(view, up)) >= 1e-9)) throw InputError(job.where, call + ": up must not be parallel to view");
    if (!(c.fovy_degrees > 0.0 && c.fovy_degrees < 180.0))
        throw InputError(job.where, call + ": fovy must be between 0 and 180 degrees (both excluded), got " +
                                        number(c.fovy_degrees));
    if (job.width < 1 || job.height < 1) throw InputError(job.where, call + ": the image has no pixels");
    check_colour(job.where, call, "ambient", job.ambient);
    check_colour(job.where, call, "miss colour (gr.set_miss_colour)", job.miss_colour);
}

void check_light(const LightDesc& l) {
    const std::string call = "gr.light";
    if (!(std::isfinite(l.radius) && l.radius >= 0.0 && l.radius <= max_coordinate))
        throw InputError(l.where, "light:set_radius: radius " + number(l.radius) + " is outside the renderer's range [0, " +
                                      number(max_coordinate) + "]");
    check_coordinates(l.where, call, "position", l.position, l.radius);
    check_colour(l.where, call, "colour", l.colour);
    bool any = false;
    for (int i = 0; i < 3; ++i) {
        const double c = l.falloff[i];
        const bool in_range = c == 0.0 || (c >= min_falloff && c <= max_falloff);
        if (!std::isfinite(c) || !in_range)
            throw InputError(l.where, call + ": falloff c" + std::to_string(i) + " = " + number(c) +
                                          " is outside the renderer's range: each coefficient must be 0 or between " +
                                          number(min_falloff) + " and " + number(max_falloff));
        any |= c > 0.0;
    }
    if (!any) throw InputError(l.where, call + ": falloff must not be all zero (intensity is divided by c0 + c1 d + c2 d^2)");
}

void check_material(const MaterialDesc& m, std::size_t textures) {
    const std::string call = "gr.material";
    check_colour(m.where, call, "kd", m.kd);
    check_colour(m.where, call, "ks", m.ks);
    if (!(std::isfinite(m.shininess) && m.shininess >= 0.0 && m.shininess <= max_shininess))
        throw InputError(m.where, call + ": shininess " + number(m.shininess) + " is outside the renderer's range [0, " +
                                      number(max_shininess) + "]");
    if (m.refractive_index) {
        const double n = *m.refractive_index;
        if (!(std::isfinite(n) && n >= min_refractive_index && n <= max_refractive_index))
            throw InputError(m.where, "material:set_ri: refractive index " + number(n) +
                                          " is outside the renderer's range [" + number(min_refractive_index) + ", " +
                                          number(max_refractive_index) + "]");
    }
    const auto bad_texture = [&](int t) { return t < -1 || (t >= 0 && static_cast<std::size_t>(t) >= textures); };
    if (bad_texture(m.texture) || bad_texture(m.bumpmap))
        throw InputError(m.where, call + ": refers to a texture that does not exist");
}

void check_transform(const NodeDesc& node, const TransformOp& op) {
    const std::string call = transform_call(op.kind);
    switch (op.kind) {
        case TransformOp::Kind::translate: check_coordinates(op.where, call, "translation", op.amount); return;
        case TransformOp::Kind::scale:
            // Scale factors up to 1e18 and down to 1e-18: beyond, the node or its inverse leaves float.
            for (int i = 0; i < 3; ++i) {
                const double s = std::fabs(op.amount[i]);
                if (std::isfinite(s) && s <= max_coordinate && s >= 1.0 / max_coordinate) continue;
                throw InputError(op.where, call + ": scale factor " + number(op.amount[i]) + " of node '" + node.name +
                                               "' is outside the renderer's range: |factor| must be between " +
                                               number(1.0 / max_coordinate) + " and " + number(max_coordinate));
            }
            return;
        case TransformOp::Kind::rotate:
            if (!std::isfinite(op.degrees) || op.axis < 0 || op.axis > 2)
                throw InputError(op.where, call + ": rotation of node '" + node.name + "' by " + number(op.degrees) +
                                               " degrees about axis " + std::to_string(op.axis) + " is not usable");
            return;
    }
}

void check_node(const NodeDesc& node, const SceneDesc& scene) {
    const std::string call = node_call(node.kind);
    const auto in_range = [](int index, std::size_t size) { return index >= 0 && static_cast<std::size_t>(index) < size; };
    if (node.material < -1 || (node.material >= 0 && !in_range(node.material, scene.materials.size())))
        throw InputError(node.where, call + ": node '" + node.name + "' refers to a material that does not exist");
    for (int child : node.children)
        if (!in_range(child, scene.nodes.size()))
            throw InputError(node.where, call + ": node '" + node.name + "' has a child that does not exist");
    const bool csg = node.kind == NodeKind::csg_union || node.kind == NodeKind::csg_intersection ||
                     node.kind == NodeKind::csg_difference;
    if (csg && !(in_range(node.csg_left, scene.nodes.size()) && in_range(node.csg_right, scene.nodes.size())))
        throw InputError(node.where, call + ": CSG node '" + node.name + "' needs two operands");
    if (node.kind == NodeKind::mesh &&
        !(in_range(node.mesh, scene.meshes.size()) && scene.meshes[static_cast<std::size_t>(node.mesh)]))
        throw InputError(node.where, call + ": node '" + node.name + "' has no mesh");
    if (node.kind == NodeKind::nh_sphere || node.kind == NodeKind::nh_box) {
        check_coordinates(node.where, call, node.kind == NodeKind::nh_sphere ? "centre" : "corner", node.position,
                          std::fabs(node.size));
        if (!(node.size > 0.0))
            throw InputError(node.where, call + ": node '" + node.name + "': size " + number(node.size) +
                                             " must be positive");
    }
    for (const TransformOp& op : node.transforms) check_transform(node, op);
}

/// The power of one caustic photon of a light (docs/CAUSTICS.md, "Photon energy"), in double so
/// that it cannot overflow here.
void check_photon_power(const RenderJob& job, const LightDesc& l) {
    const Options& o = job.options;
    if (!(l.falloff.z > 0.0) || o.caustic_num_photons <= 0) return;  // no photons from this light
    const double colour = std::fmax(l.colour.x, std::fmax(l.colour.y, l.colour.z));
    const double power = colour * 4.0 * pi * o.unit_distance * o.unit_distance * o.energy_fudge /
                         (l.falloff.z * static_cast<double>(o.caustic_num_photons));
    if (std::isfinite(power) && power <= max_photon_power) return;
    throw InputError(l.where, "gr.light: each caustic photon would carry a power of " + number(power) +
                                  " (colour x 4 pi x unit distance^2 x energy fudge / (c2 x photons) with unit distance " +
                                  number(o.unit_distance) + ", fudge " + number(o.energy_fudge) + ", c2 " +
                                  number(l.falloff.z) + "), beyond the renderer's range of " +
                                  number(max_photon_power) +
                                  ": lower --unit-distance or --energy-fudge, or raise c2 or the photon count");
}

/// The numbers among the options that shading divides by or multiplies with. The option parser
/// enforces their ranges; this catches a job whose options were set in code (the preview's knobs).
void check_options(const Options& o) {
    const auto refuse = [](const char* name, double v) {
        throw InputError(std::string("--") + name + ": " + number(v) + " is not a usable value");
    };
    if (!(std::isfinite(o.unit_distance) && o.unit_distance > 0.0 && o.unit_distance <= 1e30))
        refuse("unit-distance", o.unit_distance);
    if (!(std::isfinite(o.energy_fudge) && o.energy_fudge >= 0.0 && o.energy_fudge <= 1e30))
        refuse("energy-fudge", o.energy_fudge);
    if (!(std::isfinite(o.caustic_max_dist) && o.caustic_max_dist <= 1e30)) refuse("caustic-max-dist", o.caustic_max_dist);
    if (o.caustic_num_neighbours < 1 || o.caustic_num_neighbours > 1'000'000)
        refuse("caustic-num-neighbours", o.caustic_num_neighbours);
    if (!(std::isfinite(o.min_weight) && o.min_weight >= 0.0)) refuse("min-weight", o.min_weight);
    if (!(std::isfinite(o.roulette_weight) && o.roulette_weight >= 0.0 && o.roulette_weight <= 1.0))
        refuse("roulette-weight", o.roulette_weight);
    if (o.max_depth < 0 || o.max_depth > 64) refuse("max-depth", o.max_depth);
    if (o.aa_grid < 1 || o.aa_grid > 16) refuse("aa-grid", o.aa_grid);
    if (o.shadow_grid < 1 || o.shadow_grid > 64) refuse("shadow-grid", o.shadow_grid);
}

}  // namespace

const char* node_call(NodeKind kind) {
    switch (kind) {
        case NodeKind::group: return "gr.node";
        case NodeKind::sphere: return "gr.sphere";
        case NodeKind::cube: return "gr.cube";
        case NodeKind::cylinder: return "gr.cylinder";
        case NodeKind::cone: return "gr.cone";
        case NodeKind::nh_sphere: return "gr.nh_sphere";
        case NodeKind::nh_box: return "gr.nh_box";
        case NodeKind::mesh: return "gr.mesh";
        case NodeKind::csg_union: return "gr.union";
        case NodeKind::csg_intersection: return "gr.intersection";
        case NodeKind::csg_difference: return "gr.difference";
    }
    return "gr.node";
}

void validate_render_job(const RenderJob& job) {
    if (!job.scene) throw InputError("no scene to render");
    const SceneDesc& scene = *job.scene;
    check_options(job.options);
    check_camera(job);
    const bool caustics = caustics_needed(job);
    for (int index : job.lights) {
        if (index < 0 || static_cast<std::size_t>(index) >= scene.lights.size())
            throw InputError(job.where, "gr.render: a light in the list does not exist");
        const LightDesc& l = scene.lights[static_cast<std::size_t>(index)];
        check_light(l);
        if (caustics) check_photon_power(job, l);
    }
    for (const MaterialDesc& m : scene.materials) check_material(m, scene.textures.size());
    for (const NodeDesc& node : scene.nodes) check_node(node, scene);
}

void validate_flat_scene(const FlatScene& flat, const SceneDesc& scene) {
    // Object-space bounds of each mesh, found once however often it is instanced.
    std::vector<std::pair<glm::dvec3, glm::dvec3>> mesh_bounds(scene.meshes.size());
    std::vector<char> mesh_known(scene.meshes.size(), 0);
    auto object_bounds = [&](const PlacedPrimitive& p, glm::dvec3& lo, glm::dvec3& hi) {
        if (!p.is_mesh) {
            glm::vec3 flo, fhi;
            shape_bounds(p.shape, flo, fhi);
            lo = glm::dvec3(flo);
            hi = glm::dvec3(fhi);
            return;
        }
        const auto m = static_cast<std::size_t>(p.mesh);
        if (!mesh_known.at(m)) {
            const MeshData& mesh = *scene.meshes[m];
            glm::dvec3 mlo(0.0), mhi(0.0);
            if (!mesh.positions.empty()) mlo = mhi = glm::dvec3(mesh.positions.front());
            for (const glm::vec3& v : mesh.positions) {
                mlo = glm::min(mlo, glm::dvec3(v));
                mhi = glm::max(mhi, glm::dvec3(v));
            }
            mesh_bounds[m] = {mlo, mhi};
            mesh_known[m] = 1;
        }
        lo = mesh_bounds[m].first;
        hi = mesh_bounds[m].second;
    };
    auto check = [&](const PlacedPrimitive& p) {
        const NodeDesc& node = scene.nodes.at(static_cast<std::size_t>(p.node));
        const std::string call = node_call(node.kind);
        const glm::dmat4& m = p.object_to_world;
        const glm::dmat4 inverse = glm::inverse(m);
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (!(std::fabs(m[c][r]) <= max_coordinate && std::fabs(inverse[c][r]) <= max_coordinate))
                    throw InputError(node.where, call + ": node '" + node.name +
                                                     "' is scaled or moved beyond the renderer's range by its "
                                                     "transforms (every matrix entry, and its inverse's, within +-" +
                                                     number(max_coordinate) + ")");
        glm::dvec3 lo, hi;
        object_bounds(p, lo, hi);
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 q((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
            const glm::dvec3 w(m * glm::dvec4(q, 1.0));
            if (finite(w) && max_abs(w) <= max_coordinate) continue;
            throw InputError(node.where, call + ": node '" + node.name + "' reaches " + vector_text(w) +
                                             " in world space, beyond the renderer's range: every coordinate must "
                                             "be within +-" + number(max_coordinate) + " (single-precision rays)");
        }
    };
    for (const PlacedPrimitive& p : flat.primitives) check(p);
    for (const FlatCsgObject& object : flat.csg_objects)
        for (const PlacedPrimitive& p : object.leaves) check(p);
}

}  // namespace caustica
