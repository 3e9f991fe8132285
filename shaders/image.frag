#version 330 core
// Display of the linear radiance image: exposure, then clamp (as the batch PNG) or sRGB encoding.
// Display only: the saved PNG never goes through this shader.
uniform sampler2D u_image;   // RGB32F, row 0 = the image's top row
uniform float u_exposure;    // multiplier, 2^stops
uniform bool u_srgb;
uniform bool u_whole_pixels; // magnified by a whole factor: fetch texels directly (cheaper in llvmpipe)
in vec2 v_uv;
out vec4 out_colour;

vec3 srgb_encode(vec3 c) {
    vec3 low = 12.92 * c;
    vec3 high = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
    return mix(low, high, step(vec3(0.0031308), c));
}

void main() {
    vec3 c;
    if (u_whole_pixels) {
        ivec2 size = textureSize(u_image, 0);
        c = texelFetch(u_image, min(ivec2(v_uv * vec2(size)), size - 1), 0).rgb;
    } else {
        c = texture(u_image, v_uv).rgb;
    }
    c = clamp(c * u_exposure, 0.0, 1.0);
    if (u_srgb) c = srgb_encode(c);
    else c = floor(c * 255.0) / 255.0;  // as the batch PNG: x255 and truncated (A7)
    out_colour = vec4(c, 1.0);
}
