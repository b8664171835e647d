#version 330 core
// The wireframe overlay: one flat colour, drawn with glPolygonMode(GL_LINE) over the shaded
// surface (render/clay_renderer.cpp offsets the surface's depth so the lines win).
uniform vec4 uWireSrgba;  // sRGB 0..1 with alpha; blended over the surface

out vec4 fragColour;

void main() {
    fragColour = uWireSrgba;
}
