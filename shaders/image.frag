#version 330 core
// Display of the linear radiance image: exposure, then clamp (as the batch PNG) or sRGB encoding.
// Display only: the saved image never goes through this shader. Kept free of branches: llvmpipe
// (the software GL of Xvfb and OSMesa) runs the code of every branch, and this quad is the largest
// part of a frame's drawing (docs/PERFORMANCE.md). The comparisons live in image_compare.frag.
// Magnified pixels stay sharp through the texture's GL_NEAREST magnification filter.
uniform sampler2D u_image;   // RGB32F, row 0 = the image's top row
uniform float u_exposure;    // multiplier, 2^stops
uniform float u_srgb;        // 1: sRGB transfer curve, 0: x255 and truncated, as the batch PNG
in vec2 v_uv;
out vec4 out_colour;

void main() {
    vec3 c = clamp(texture(u_image, v_uv).rgb * u_exposure, 0.0, 1.0);
    vec3 srgb = mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
    vec3 linear = floor(c * 255.0) / 255.0;
    out_colour = vec4(mix(linear, srgb, u_srgb), 1.0);
}
