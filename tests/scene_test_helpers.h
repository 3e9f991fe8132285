// Small helpers several test files share: the error a script load throws, and a surface hit on
// an analytic shape as RenderScene fills it.
#pragma once

#include "core/geometry/ray.h"
#include "core/geometry/shapes.h"
#include "core/lua/scene_loader.h"
#include "core/scene/source_location.h"
#include "tests/temp_folder.h"

#include <string>
#include <vector>

namespace caustica::testing {

/// The message of the InputError that loading `path` throws ("(no error)" when it loads).
inline std::string load_error(const std::string& path, const LoadSettings& settings = {}) {
    try {
        load_scene_script(path, settings);
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

/// The first gr.render of a script given as text (written to a temporary folder and loaded as
/// `caustica render` loads it), with --reproducible and --silent on.
inline RenderJob load_first_job(const std::string& source) {
    TempFolder folder("caustica_scene");
    RenderJob job = load_scene_script(folder.write("scene.lua", source)).renders.at(0);
    job.options.reproducible = true;
    job.options.silent = true;
    return job;
}

/// `balls` (Lua making the nodes named in `names`) above a white floor, lit from 4 above and seen
/// from 5 above at size x size pixels with a `fov` degree view; `options` is the scene's
/// gr.option text (or none). Rays that miss are black.
inline RenderJob balls_over_floor_job(const std::string& options, const std::string& balls,
                                      const std::vector<std::string>& names, int size, int fov) {
    std::string lua = options.empty() ? std::string() : "gr.option('" + options + "')\n";
    lua += balls + R"(floor = gr.cube('floor')
floor:translate(0, -1, 0)
floor:scale(4, 1, 4)
floor:set_material(gr.material({1, 1, 1}, {0, 0, 0}, 0))
root = gr.node('root')
root:add_child(floor)
)";
    for (const std::string& name : names) lua += "root:add_child(" + name + ")\n";
    lua += "gr.render(root, 'balls.png', " + std::to_string(size) + ", " + std::to_string(size) +
           ", {0, 5, 0.01}, {0, -1, 0}, {0, 0, -1}, " + std::to_string(fov) +
           ", {0, 0, 0}, {gr.light({0.3, 4, 0.1}, {1, 1, 1}, {0, 0, 0.1})})\n";
    RenderJob job = load_first_job(lua);
    job.miss_colour = glm::dvec3(0.0);
    return job;
}

/// A glass ball (index 1.5, ks 1) focusing a point light onto a white floor, seen from above, 40 x
/// 40, progressive and caustics only with 40 000 photons a pass: the focus (far above 1), the ring
/// of light around it and the ball's shadow form a caustic with sharp edges.
inline RenderJob glass_ball_focus_job() {
    return balls_over_floor_job("--integrator progressive --draw-caustics-only --caustic-num-photons 40000", R"(
glass = gr.material({0, 0, 0}, {1, 1, 1}, 20)
glass:set_ri(1.5)
ball = gr.nh_sphere('ball', {0, 1.2, 0}, 0.5)
ball:set_material(glass)
)", {"ball"}, 40, 24);
}

/// A glass ball (ks 0.9) and a mirror ball (ks 0.8) on a white floor, lit and seen from above at
/// 48 x 48: caustics of both kinds. `options`, when given, is the scene's gr.option text.
inline RenderJob glass_and_mirror_balls_job(const std::string& options = "") {
    return balls_over_floor_job(options, R"(
glass = gr.material({0, 0, 0}, {0.9, 0.9, 0.9}, 20)
glass:set_ri(1.5)
mirror = gr.material({0, 0, 0}, {0.8, 0.8, 0.8}, 20)
ball = gr.nh_sphere('ball', {-0.8, 1.2, 0}, 0.5)
ball:set_material(glass)
shiny = gr.nh_sphere('shiny', {0.9, 0.6, 0}, 0.5)
shiny:set_material(mirror)
)", {"ball", "shiny"}, 48, 60);
}

/// A hit at object point p of an analytic shape placed with object space = world space, as
/// RenderScene fills it (uv and the bump tangents of docs/TEXTURES.md included).
inline SurfaceHit shape_hit(const Shape& shape, const glm::vec3& p, int face, const glm::vec3& outward) {
    SurfaceHit hit;
    hit.position = hit.object_position = p;
    hit.normal = glm::normalize(outward);
    hit.face = face;
    hit.material = 0;
    hit.shape_kind = static_cast<int>(shape.kind);
    hit.uv = shape_uv(shape, p, face);
    shape_tangents(shape, p, face, hit.dpdu, hit.dpdv);
    return hit;
}

}  // namespace caustica::testing
