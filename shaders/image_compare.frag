#version 330 core
// The A/B comparisons of docs/INSPECTION.md (only while a reference of the image's size is shown:
// image.frag draws the plain image, at a third of this shader's cost in llvmpipe, which runs the
// code of every branch even when a uniform skips it). Display only.
uniform sampler2D u_image;     // RGB32F, row 0 = the image's top row (A: the current render)
uniform sampler2D u_reference; // RGB32F of the same size (B), bound only when u_mode != 0
uniform float u_exposure;      // multiplier, 2^stops
uniform vec3 u_tonemap;        // weights of the curves clamp, Reinhard, filmic (image.frag's TONE_CURVE)
uniform bool u_srgb;
uniform bool u_whole_pixels;   // magnified by a whole factor: fetch texels directly (cheaper in llvmpipe)
uniform int u_mode;            // 0 image, 1 split (A left of u_split, B right), 2 |A - B| x u_gain, 3 relative error
uniform float u_split;         // split position, fraction of the image width
uniform float u_gain;          // difference multiplier
uniform float u_epsilon;       // relative error: |A - B|_1 / max(|B|_1, u_epsilon)
in vec2 v_uv;
out vec4 out_colour;

vec3 srgb_encode(vec3 c) {
    vec3 low = 12.92 * c;
    vec3 high = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
    return mix(low, high, step(vec3(0.0031308), c));
}

vec3 fetch(sampler2D image) {
    if (u_whole_pixels) {
        ivec2 size = textureSize(image, 0);
        return texelFetch(image, min(ivec2(v_uv * vec2(size)), size - 1), 0).rgb;
    }
    return texture(image, v_uv).rgb;
}

// The view transform's curves, as image.frag applies them.
vec3 tone(vec3 x) {
    vec3 clamped = min(x, 1.0);
    vec3 reinhard = x / (1.0 + x);
    vec3 f = min(x, 8.0);
    vec3 filmic = min(f * (2.51 * f + 0.03) / (f * (2.43 * f + 0.59) + 0.14), 1.0);
    return u_tonemap.x * clamped + u_tonemap.y * reinhard + u_tonemap.z * filmic;
}

// The relative error's colour ramp: keep in step with heat_colour() in ui/inspection.cpp.
vec3 heat(float t) {
    const vec3 stops[5] = vec3[5](vec3(0.0, 0.0, 0.25), vec3(0.0, 0.35, 1.0), vec3(0.0, 0.8, 0.3),
                                  vec3(1.0, 0.9, 0.0), vec3(1.0, 0.0, 0.0));
    float s = clamp(t, 0.0, 1.0) * 4.0;
    int i = min(int(s), 3);
    return mix(stops[i], stops[i + 1], s - float(i));
}

void main() {
    vec3 c = fetch(u_image);
    if (u_mode == 1) {
        if (v_uv.x >= u_split) c = fetch(u_reference);
    } else if (u_mode == 2) {
        c = abs(c - fetch(u_reference)) * u_gain;
    } else if (u_mode == 3) {
        vec3 b = fetch(u_reference);
        vec3 d = abs(c - b);
        float relative = (d.r + d.g + d.b) / max(abs(b.r) + abs(b.g) + abs(b.b), u_epsilon);
        // 0.1 % and below at the bottom of the ramp, 100 % and above at the top, log-spaced.
        float t = relative > 1e-3 ? min(1.0, (log2(relative) / log2(10.0) + 3.0) / 3.0) : 0.0;
        out_colour = vec4(heat(t), 1.0);
        return;
    }
    c = tone(max(c * u_exposure, 0.0));
    if (u_srgb) c = srgb_encode(c);
    else c = floor(c * 255.0) / 255.0;  // as the batch PNG: x255 and truncated
    out_colour = vec4(c, 1.0);
}
