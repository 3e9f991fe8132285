#version 330 core
// The rendered image as a rectangle in window pixels; corners come from gl_VertexID (no buffers).
uniform vec4 u_rect;    // left, top, width, height of the image in window pixels (y down)
uniform vec2 u_window;  // window size in pixels
out vec2 v_uv;          // (0, 0) at the image's top-left pixel corner

void main() {
    vec2 corner = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
    vec2 pixel = u_rect.xy + corner * u_rect.zw;
    v_uv = corner;
    gl_Position = vec4(pixel.x / u_window.x * 2.0 - 1.0, 1.0 - pixel.y / u_window.y * 2.0, 0.0, 1.0);
}
