#version 330 core
// Display of the linear radiance image: the view transform of ui/view_transform.h (exposure, the
// --tonemap curve, then x255 truncated as the batch PNG, or sRGB encoding), so the viewport shows
// what `caustica render --exposure E --tonemap X` writes to a PNG; display_value() there is this
// formula on the CPU, keep them in step. Display only: the saved image never goes through this
// shader. Kept free of branches: llvmpipe (the software GL of Xvfb and OSMesa) runs the code of
// every branch, and this quad is the largest part of a frame's drawing (docs/PERFORMANCE.md), so
// the curve is chosen when the program is built (TONE_CURVE, one program per curve) and the
// comparisons live in image_compare.frag. Magnified pixels stay sharp through the texture's
// GL_NEAREST magnification filter.
uniform sampler2D u_image;   // RGB32F, row 0 = the image's top row
uniform float u_exposure;    // multiplier, 2^stops
uniform float u_srgb;        // 1: sRGB transfer curve, 0: x255 and truncated, as the batch PNG
in vec2 v_uv;
out vec4 out_colour;

#ifndef TONE_CURVE
#define TONE_CURVE 0
#endif

// The curves of core/io/tonemap.h: 0 clamp, 1 Reinhard, 2 filmic.
vec3 tone(vec3 x) {
#if TONE_CURVE == 1
    return x / (1.0 + x);
#elif TONE_CURVE == 2
    vec3 f = min(x, 8.0);
    return min(f * (2.51 * f + 0.03) / (f * (2.43 * f + 0.59) + 0.14), 1.0);
#else
    return min(x, 1.0);
#endif
}

void main() {
    vec3 c = tone(max(texture(u_image, v_uv).rgb * u_exposure, 0.0));
    vec3 srgb = mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
    vec3 linear = floor(c * 255.0) / 255.0;
    out_colour = vec4(mix(linear, srgb, u_srgb), 1.0);
}
