#version 330 core
// Points mode's fragment stage: keeps the fragments of the point sprite that lie on the vertex's
// disc, a circle in its tangent plane (an ellipse on screen), and lights them as the lit clay
// (clay_shading.frag, linked with it). Botsch and Kobbelt 2003, "High-quality point-based
// rendering on modern GPUs": the sprite's offset d, in disc radii, lies on the tangent plane at
// depth offset -(n.x d.x + n.y d.y) / n.z; inside where |(d, depth)| <= 1. Each fragment takes
// the depth of its point on the disc, so where discs overlap the surface nearer the eye wins
// (a disc's centre depth would let a tilted disc at an edge cover the face beside it).
in vec3 vPositionEye;
in vec3 vNormalEye;
in vec4 vColour;
in float vRadius;  // m: the disc's

uniform int uOrthographic;  // 1: the view direction is -Z everywhere
uniform mat4 uProjection;   // eye to clip

out vec4 fragColour;

vec3 shadeClay(vec3 n, vec3 v, vec4 colour);  // clay_shading.frag

void main() {
    vec3 n = normalize(vNormalEye);
    vec3 v = uOrthographic != 0 ? vec3(0.0, 0.0, 1.0) : normalize(-vPositionEye);
    // A disc seen edge-on may turn a little away over its sprite (points.vert culls the others).
    if (dot(n, v) < 0.0) n = -n;
    vec2 d = vec2(2.0 * gl_PointCoord.x - 1.0, 1.0 - 2.0 * gl_PointCoord.y);
    // Discs seen edge-on are kept no thinner than a fifth of their width.
    float depth = -(n.x * d.x + n.y * d.y) / max(n.z, 0.2);
    if (dot(d, d) + depth * depth > 1.0) discard;
    float zEye = vPositionEye.z + depth * vRadius;
    vec2 clipZW = vec2(uProjection[2][2] * zEye + uProjection[3][2], uProjection[2][3] * zEye + uProjection[3][3]);
    gl_FragDepth = 0.5 * clipZW.x / clipZW.y + 0.5;
    fragColour = vec4(shadeClay(n, v, vColour), 1.0);
}
