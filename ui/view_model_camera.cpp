// The ViewModel's camera: orbit, zoom, pan and the orbit's target, back to the script's camera or
// to a bookmark, and a camera as gr.render arguments.
#include "ui/view_model.h"

#include "core/render/orbit_target.h"
#include "core/scene/camera.h"
#include "ui/view_model_internal.h"

#include <cmath>

namespace caustica::ui {

std::string camera_lua(const CameraDesc& c) {
    auto v = [](glm::dvec3 p) {
        return std::string("{").append(exact_number(p.x)).append(", ").append(exact_number(p.y)).append(", ")
            .append(exact_number(p.z)).append("}");
    };
    return v(c.eye) + ", " + v(c.view) + ", " + v(c.up) + ", " + exact_number(c.fovy_degrees);
}

// --- camera

void ViewModel::orbit(double yaw_degrees, double pitch_degrees) {
    if (!scene_ || (yaw_degrees == 0.0 && pitch_degrees == 0.0)) return;
    orbit_.orbit(yaw_degrees, pitch_degrees);
    mark_dirty();
}

void ViewModel::zoom(double steps) {
    if (!scene_ || steps == 0.0) return;
    orbit_.zoom(std::pow(0.9, steps));
    mark_dirty();
}

void ViewModel::pan(glm::dvec2 image_pixels) {
    if (!scene_ || (image_pixels.x == 0.0 && image_pixels.y == 0.0)) return;
    const RenderJob& shown = driver_.has_job() ? driver_.job() : current_job();
    orbit_.pan_pixels(image_pixels, shown.width, shown.height);
    mark_dirty();
}

bool ViewModel::set_target_at(glm::vec2 image_pixel) {
    if (!scene_) return false;
    const RenderJob job = driver_.has_job() ? driver_.job() : current_job();
    const Camera camera(orbit_.desc(), job.width, job.height);
    glm::vec3 point;
    if (!driver_.session().pick(camera.generate(image_pixel.x, image_pixel.y), point)) return false;
    orbit_.set_target(glm::dvec3(point));
    target_known_ = true;
    mark_dirty();
    return true;
}

void ViewModel::reset_camera() {
    if (!scene_) return;
    const CameraDesc& camera = scene_->renders[inputs_.render_index].camera;
    orbit_ = OrbitCamera(camera, default_target_distance(camera));
    target_known_ = false;
    mark_dirty();
}

void ViewModel::resolve_target() {
    // The initial orbit target: on the script's view axis, at the depth of the centre of what the
    // camera sees (docs/PREVIEW.md, "Keys and mouse"), so that an orbit keeps the scene in view.
    if (target_known_ || !scene_) return;
    if (orbit_.moved()) {
        target_known_ = true;
        return;
    }
    if (!driver_.has_job() || driver_.job().scene != scene_->renders[inputs_.render_index].scene) return;
    const SessionProgress& p = driver_.progress();
    if (p.tiles_total == 0 && !p.finished) return;  // the scene is not built yet
    const RenderJob& job = driver_.job();
    orbit_.set_target_distance(visible_centre_distance(driver_.session(), orbit_.desc(), job.width, job.height));
    target_known_ = true;
    if (pending_orbit_) {  // --orbit: around the same target an interactive drag would use
        orbit(pending_orbit_->x, pending_orbit_->y);
        pending_orbit_.reset();
    }
}

void ViewModel::go_to_camera(const CameraDesc& camera) {
    if (!scene_) return;
    const CameraDesc& script = scene_->renders[inputs_.render_index].camera;
    if (same_camera(camera, script)) {
        orbit_ = OrbitCamera(script, default_target_distance(script));
        target_known_ = false;
    } else {  // a moved camera: it stays on a reload, and the first surface on its axis becomes the target
        CameraDesc moved = script;
        moved.eye = camera.eye;
        moved.view = camera.view;
        moved.up = camera.up;
        orbit_ = OrbitCamera(moved, default_target_distance(moved));
        orbit_.set_target(orbit_.target());
        target_known_ = false;
    }
    mark_dirty();
}

}  // namespace caustica::ui
