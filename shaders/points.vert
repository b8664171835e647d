#version 330 core
// Points mode's vertex stage (Kizamu paper 6.1, point rendering for fast global views): each
// mesh vertex is a disc on its tangent plane, as large on screen as its local spacing there.
// Attributes as render/gpu_mesh.h binds them, plus the spacing: the longest mesh edge at the
// vertex (m).
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 aColour;
layout(location = 3) in float aSpacing;

uniform mat4 uView;             // world to eye
uniform mat4 uProjection;       // eye to clip
uniform mat3 uNormalView;       // world normals to eye: the view's rotation
uniform float uViewportHeight;  // pixels
uniform float uMaxPointSize;    // pixels: the driver's largest point

out vec3 vPositionEye;
out vec3 vNormalEye;
out vec4 vColour;
out float vRadius;  // m: the disc's

void main() {
    vec4 p = uView * vec4(aPosition, 1.0);
    vPositionEye = p.xyz;
    vNormalEye = uNormalView * aNormal;
    vColour = aColour;
    gl_Position = uProjection * p;
    // A disc of radius 0.6 spacing covers the triangles around its vertex (their circumradius is
    // at most the longest edge over sqrt(3)). Its diameter in pixels: projection[1][1] maps eye
    // units at depth w to half the viewport height (w is 1 in an orthographic view).
    float radius = 0.6 * aSpacing;
    vRadius = radius;
    gl_PointSize = clamp(radius * uProjection[1][1] * uViewportHeight / gl_Position.w, 1.0, uMaxPointSize);
    // Discs facing away are culled (moved outside the clip volume), as splatting does: on closed
    // clay a front-facing disc covers that place, and a back-facing one reaching past it would
    // show as a dark patch. Spacing 0 marks slack vertices of the tiled mesh: culled too.
    vec3 towardsEye = uProjection[3][3] == 1.0 ? vec3(0.0, 0.0, 1.0) : -p.xyz;
    if (dot(vNormalEye, towardsEye) < 0.0 || aSpacing <= 0.0) gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
}
