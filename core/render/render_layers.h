// `caustica render --layers` (docs/OUTPUT.md, "Layers"): the image's light split into the layers
// of core/integrators/shading_layer.h, rendered by one integrator per layer alongside the image
// (TileContext::layers), and the multilayer OpenEXR that holds them.
#pragma once

#include "core/integrators/integrator.h"
#include "core/io/image_io.h"
#include "core/render/layer_image.h"
#include "core/render/tile_renderer.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace caustica {

/// Why a job cannot write layers to `path`, "" when it can: the output must be OpenEXR, and no
/// debug view may replace the shading.
std::string layers_refusal(const Options& options, const std::string& path);

/// The integrators and images of --layers for one render: nothing when the job's options do not ask
/// for layers (no integrator is made, no image allocated, the tile passes trace nothing more).
class LayerRender {
public:
    /// `setup` is the image's (photon maps set); each layer's integrator gets a copy keeping its
    /// layer. Renders layers when options.layers and `wanted`.
    LayerRender(const ShadingSetup& setup, const Options& options, int width, int height, bool wanted = true);
    LayerRender(const LayerRender&) = delete;  // the integrators point into setups_
    LayerRender& operator=(const LayerRender&) = delete;

    /// The tile passes' targets (TileContext::layers), null when no layers are rendered.
    const std::vector<LayerTarget>* targets() const { return targets_.empty() ? nullptr : &targets_; }
    /// The rendered layers, in written_layers order (moved out: call once the passes are done).
    std::vector<LayerImage> take_images();

private:
    static constexpr std::size_t count = std::size(written_layers);
    std::array<ShadingSetup, count> setups_;  // the integrators keep references: never moved
    std::vector<std::unique_ptr<Integrator>> integrators_;
    std::vector<LayerImage> images_;
    std::vector<LayerTarget> targets_;
};

/// The OpenEXR channels of an image and its layers: R, G, B, A (1) of the image, then
/// "direct.R" ... "background.B", "albedo.R/G/B" and "normal.X/Y/Z". `exposure_stops` scales the
/// image and the light layers (2^stops, as --exposure scales an EXR), never albedo or normal:
/// `scaled` holds the scaled copies the channels point into.
std::vector<ExrChannel> layer_channels(const Image& image, const std::vector<LayerImage>& layers, float exposure_stops,
                                       std::vector<Image>& scaled);

}  // namespace caustica
