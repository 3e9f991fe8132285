#version 330 core
// Display of the linear radiance image: the view transform of ui/view_transform.h (exposure, the
// --tonemap curve, then x255 truncated as the batch PNG, or sRGB encoding), so the viewport shows
// what `caustica render --exposure E --tonemap X` writes to a PNG; display_value() there is this
// formula on the CPU, keep them in step. Display only: the saved image never goes through this
// shader. Kept free of branches: llvmpipe (the software GL of Xvfb and OSMesa) runs the code of
// every branch, and this quad is the largest part of a frame's drawing (docs/PERFORMANCE.md). The
// comparisons live in image_compare.frag. Magnified pixels stay sharp through the texture's
// GL_NEAREST magnification filter.
uniform sampler2D u_image;   // RGB32F, row 0 = the image's top row
uniform float u_exposure;    // multiplier, 2^stops
uniform vec3 u_tonemap;      // weights of the curves clamp, Reinhard, filmic: one of them 1 (tonemap_weights)
uniform float u_srgb;        // 1: sRGB transfer curve, 0: x255 and truncated, as the batch PNG
in vec2 v_uv;
out vec4 out_colour;

// The three curves of core/io/tonemap.h, weighted.
vec3 tone(vec3 x) {
    vec3 clamped = min(x, 1.0);
    vec3 reinhard = x / (1.0 + x);
    vec3 f = min(x, 8.0);
    vec3 filmic = min(f * (2.51 * f + 0.03) / (f * (2.43 * f + 0.59) + 0.14), 1.0);
    return u_tonemap.x * clamped + u_tonemap.y * reinhard + u_tonemap.z * filmic;
}

void main() {
    vec3 c = tone(max(texture(u_image, v_uv).rgb * u_exposure, 0.0));
    vec3 srgb = mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
    vec3 linear = floor(c * 255.0) / 255.0;
    out_colour = vec4(mix(linear, srgb, u_srgb), 1.0);
}
