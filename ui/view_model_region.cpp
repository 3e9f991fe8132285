// The ViewModel's render region (docs/PREVIEW.md, "Render region"): the pixels every pass goes
// to, kept by the driver, which hands it to the session without restarting the accumulation.
#include "ui/view_model.h"

#include "ui/view_model_internal.h"

namespace caustica::ui {

void ViewModel::set_render_region(const RenderRegion& region) {
    const RenderJob job = scene_ ? current_job() : driver_.job();
    region_camera_ = job.camera;
    region_width_ = job.width;
    region_height_ = job.height;
    driver_.set_region(clamp_region(region, job.width, job.height));
}

void ViewModel::clear_region_of_another_view(const RenderJob& next) {
    if (render_region().empty()) return;
    if (!same_camera(next.camera, region_camera_) || next.width != region_width_ || next.height != region_height_)
        driver_.set_region({});
}

}  // namespace caustica::ui
