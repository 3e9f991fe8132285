#version 330 core
// Projection-map overlay: triangles given in image pixels, placed where the image is shown.
layout(location = 0) in vec2 a_position;  // image pixels (y down)
layout(location = 1) in vec4 a_colour;
uniform vec4 u_rect;        // left, top, width, height of the image in window pixels
uniform vec2 u_image_size;  // image size in pixels
uniform vec2 u_window;      // window size in pixels
out vec4 v_colour;

void main() {
    vec2 pixel = u_rect.xy + a_position / u_image_size * u_rect.zw;
    v_colour = a_colour;
    gl_Position = vec4(pixel.x / u_window.x * 2.0 - 1.0, 1.0 - pixel.y / u_window.y * 2.0, 0.0, 1.0);
}
