#version 330 core
// The cells debug view's lines: their level's colour, blended over the clay.
in vec3 vColourSrgb;

uniform float uAlpha;  // opacity of the lines

out vec4 fragColour;

void main() {
    fragColour = vec4(vColourSrgb, uAlpha);
}
