// Small helpers several test files share: the error a script load throws, and a surface hit on
// an analytic shape as RenderScene fills it.
#pragma once

#include "core/geometry/ray.h"
#include "core/geometry/shapes.h"
#include "core/lua/scene_loader.h"
#include "core/scene/source_location.h"
#include "temp_folder.h"

#include <string>

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

/// A glass ball (index 1.5, ks 1) focusing a point light onto a white floor, seen from above, 40 x
/// 40, progressive and caustics only with 40 000 photons a pass: the focus (far above 1), the ring
/// of light around it and the ball's shadow form a caustic with sharp edges.
inline RenderJob glass_ball_focus_job() {
    RenderJob job = load_first_job(R"(
gr.option('--integrator progressive --draw-caustics-only --caustic-num-photons 40000')
glass = gr.material({0, 0, 0}, {1, 1, 1}, 20)
glass:set_ri(1.5)
ball = gr.nh_sphere('ball', {0, 1.2, 0}, 0.5)
ball:set_material(glass)
floor = gr.cube('floor')
floor:translate(0, -1, 0)
floor:scale(4, 1, 4)
floor:set_material(gr.material({1, 1, 1}, {0, 0, 0}, 0))
root = gr.node('root')
root:add_child(floor)
root:add_child(ball)
gr.render(root, 'focus.png', 40, 40, {0, 5, 0.01}, {0, -1, 0}, {0, 0, -1}, 24, {0, 0, 0},
          {gr.light({0.3, 4, 0.1}, {1, 1, 1}, {0, 0, 0.1})})
)");
    job.miss_colour = glm::dvec3(0.0);
    return job;
}

/// A hit at object point p of an analytic shape placed with object space = world space, as
/// RenderScene fills it (uv and the A2 tangents included).
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
