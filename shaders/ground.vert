#version 330 core
// The ground: one square in the plane z = uGroundZ (world, Z up) under the model, made from
// gl_VertexID (drawn as a 4-vertex triangle strip with no vertex buffer).
uniform mat4 uView;          // world to eye
uniform mat4 uProjection;    // eye to clip
uniform vec2 uCentre;        // m, world x and y of the square's centre
uniform float uHalfSize;     // m, half the square's side
uniform float uGroundZ;      // m, world height of the plane

out vec2 vGround;            // m, world x and y

void main() {
    vec2 corner = vec2((gl_VertexID & 1) == 0 ? -1.0 : 1.0, (gl_VertexID & 2) == 0 ? -1.0 : 1.0);
    vGround = uCentre + corner * uHalfSize;
    gl_Position = uProjection * uView * vec4(vGround, uGroundZ, 1.0);
}
