#version 330 core
// The tool's marks in one colour each (sRGB with alpha, blended).
uniform vec4 uColourSrgba;
out vec4 fragColour;
void main() { fragColour = uColourSrgba; }
