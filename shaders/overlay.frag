#version 330 core
// Flat colour of the overlay's outline, cells and light marker (blended over the image).
in vec4 v_colour;
out vec4 out_colour;

void main() {
    out_colour = v_colour;
}
