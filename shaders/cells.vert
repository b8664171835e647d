#version 330 core
// The cells debug view: the edges of the ADF's leaf cells near the surface (render/
// cell_box_lines.h), coloured by octree level from coarse (cool) to fine (warm).
layout(location = 0) in vec3 aPosition;  // m, world
layout(location = 1) in float aLevel;    // octree level

uniform mat4 uView;         // world to eye
uniform mat4 uProjection;   // eye to clip
uniform vec2 uLevelRange;   // the coarsest and finest levels drawn

out vec3 vColourSrgb;

void main() {
    float t = uLevelRange.y > uLevelRange.x ? (aLevel - uLevelRange.x) / (uLevelRange.y - uLevelRange.x) : 1.0;
    vColourSrgb = mix(vec3(0.20, 0.55, 0.95), vec3(0.95, 0.35, 0.15), t);
    gl_Position = uProjection * uView * vec4(aPosition, 1.0);
}
