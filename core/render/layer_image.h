// One rendered layer of --layers (docs/OUTPUT.md, "Layers"): what a render returns beside its image.
#pragma once

#include "core/integrators/shading_layer.h"
#include "core/render/image.h"

namespace caustica {

/// One rendered layer.
struct LayerImage {
    ShadingLayer layer = ShadingLayer::direct;
    Image image;
};

}  // namespace caustica
