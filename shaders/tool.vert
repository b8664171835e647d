#version 330 core
// The tool's marks, made from gl_VertexID (no vertex buffer):
//  uMode 0: the brush ring, a 64-vertex line loop of radius uRadius round uCentre in the plane
//           perpendicular to uNormal (the surface under the tool);
//  uMode 1: the drop line, 2 vertices from uCentre straight down to the floor (z = uFloorZ);
//  uMode 2: the tool's spot on the floor, a 34-vertex triangle fan (centre, then a circle).
// Depth cues for a tool in 3D on a 2D screen (Galyean and Hughes' stage, simplified): the spot
// and the line say where the tool stands over the floor and how high.
uniform mat4 uView;
uniform mat4 uProjection;
uniform vec3 uCentre;   // m, world
uniform vec3 uNormal;   // unit, world
uniform float uRadius;  // m
uniform float uFloorZ;  // m, world
uniform int uMode;

void main() {
    const float kTwoPi = 6.28318530718;
    vec3 p;
    if (uMode == 0) {
        vec3 a = normalize(abs(uNormal.z) < 0.9 ? cross(uNormal, vec3(0.0, 0.0, 1.0)) : cross(uNormal, vec3(1.0, 0.0, 0.0)));
        vec3 b = cross(uNormal, a);
        float t = kTwoPi * float(gl_VertexID) / 64.0;
        p = uCentre + uRadius * (cos(t) * a + sin(t) * b);
    } else if (uMode == 1) {
        p = gl_VertexID == 0 ? uCentre : vec3(uCentre.xy, uFloorZ);
    } else {
        float t = kTwoPi * float(gl_VertexID - 1) / 32.0;
        p = gl_VertexID == 0 ? vec3(uCentre.xy, uFloorZ) : vec3(uCentre.xy + uRadius * vec2(cos(t), sin(t)), uFloorZ);
    }
    gl_Position = uProjection * uView * vec4(p, 1.0);
}
