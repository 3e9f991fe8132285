#include "core/render/render_layers.h"

#include "core/integrators/registry.h"

namespace caustica {

std::string layers_refusal(const Options& o, const std::string& path) {
    if (image_format_of(path) != ImageFormat::exr)
        return "--layers: '" + path + "': layers need an OpenEXR output (.exr); PNG and PFM hold one image";
    if (o.debug_view() || o.show_layer != ShadingLayer::beauty)
        return "--layers: a debug view (--draw-aa, --draw-caustic-map, --show-projection-map, --draw-caustics-only, "
               "--draw-gi-map, --draw-gi-only, --show-layer) replaces the shading the layers split: drop it";
    return {};
}

LayerRender::LayerRender(const ShadingSetup& setup, const Options& options, int width, int height, bool wanted) {
    if (!options.layers || !wanted) return;
    for (std::size_t i = 0; i < count; ++i) {
        ShadingSetup& s = setups_[i];
        s = setup;
        s.layer = written_layers[i];
        integrators_.push_back(make_integrator(options.integrator, s, options));
        images_.push_back({written_layers[i], Image(width, height)});
    }
    for (std::size_t i = 0; i < count; ++i) targets_.push_back({integrators_[i].get(), &images_[i].image});
}

std::vector<LayerImage> LayerRender::take_images() {
    targets_.clear();
    return std::move(images_);
}

std::vector<ExrChannel> layer_channels(const Image& image, const std::vector<LayerImage>& layers, float exposure_stops,
                                       std::vector<Image>& scaled) {
    const float scale = exposure_scale(exposure_stops);
    auto exposed = [&](const Image& source) -> const Image& {
        if (exposure_stops == 0.0f) return source;
        Image copy = source;
        for (glm::vec3& p : copy.pixels) p *= scale;
        scaled.push_back(std::move(copy));
        return scaled.back();
    };
    scaled.clear();
    scaled.reserve(layers.size() + 1);  // the channels point into it: no reallocation
    const Image& beauty = exposed(image);
    std::vector<ExrChannel> channels = {{"R", &beauty, 0}, {"G", &beauty, 1}, {"B", &beauty, 2}, {"A", nullptr, 0, 1.0f}};
    for (const LayerImage& layer : layers) {
        const Image& source = is_surface_layer(layer.layer) ? layer.image : exposed(layer.image);
        const bool vector = layer.layer == ShadingLayer::normal;
        const char* components[3] = {vector ? "X" : "R", vector ? "Y" : "G", vector ? "Z" : "B"};
        for (int c = 0; c < 3; ++c)
            channels.push_back({std::string(layer_name(layer.layer)) + "." + components[c], &source, c});
    }
    return channels;
}

}  // namespace caustica
