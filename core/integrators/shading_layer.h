// The layers of `caustica render --layers` (docs/OUTPUT.md, "Layers"): which part of the light an
// integrator keeps. Every term a camera path adds is of one kind, wherever along the path it is
// added (seen directly, or through mirrors and glass with the path's weight):
//   direct      the Phong terms of the lights (the highlights included)
//   indirect    the diffuse interreflection: the GI map's estimate, or the scene's ambient term
//               that stands in for it
//   caustic     the caustic photon map's estimate
//   background  what rays that leave the scene bring back (miss colour, the --rays sunburst), and
//               the white a classic ray deeper than its limit returns ("deep rays")
// The four add up to the image. albedo and normal are the first surface's kd and shading normal.
#pragma once

namespace caustica {

enum class ShadingLayer {
    beauty,  ///< everything: the image
    direct,
    indirect,
    caustic,
    background,
    albedo,  ///< kd of the first surface hit (0 where the ray leaves the scene)
    normal,  ///< the shading normal there, world space, as the integrator shades with it
};

/// The layers --layers writes, in the file's order.
inline constexpr ShadingLayer written_layers[] = {ShadingLayer::direct, ShadingLayer::indirect, ShadingLayer::caustic,
                                                  ShadingLayer::background, ShadingLayer::albedo, ShadingLayer::normal};

/// Whether an integrator shading `layer` keeps a term of kind `term` (one of the four light kinds).
inline bool keeps(ShadingLayer layer, ShadingLayer term) { return layer == ShadingLayer::beauty || layer == term; }

/// Whether `layer` is a property of the first surface rather than light (albedo, normal).
inline bool is_surface_layer(ShadingLayer layer) { return layer == ShadingLayer::albedo || layer == ShadingLayer::normal; }

/// "direct", "indirect", "caustic", "background", "albedo", "normal" ("" for beauty): the
/// layer's name in the OpenEXR channels ("caustic.R").
inline const char* layer_name(ShadingLayer layer) {
    switch (layer) {
        case ShadingLayer::beauty: return "";
        case ShadingLayer::direct: return "direct";
        case ShadingLayer::indirect: return "indirect";
        case ShadingLayer::caustic: return "caustic";
        case ShadingLayer::background: return "background";
        case ShadingLayer::albedo: return "albedo";
        case ShadingLayer::normal: return "normal";
    }
    return "";
}

}  // namespace caustica
