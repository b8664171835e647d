#version 330 core
// The clay's vertex stage, shared by every surface mode (clay.frag, matcap.frag, wire.frag).
// Attributes as render/gpu_mesh.h binds them: positions in metres (world), unit normals,
// sRGB colours with alpha 1 where painted and 0 where not.
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 aColour;

uniform mat4 uView;        // world to eye
uniform mat4 uProjection;  // eye to clip
uniform mat3 uNormalView;  // world normals to eye: the view's rotation

out vec3 vPositionEye;
out vec3 vNormalEye;
out vec4 vColour;

void main() {
    vec4 p = uView * vec4(aPosition, 1.0);
    vPositionEye = p.xyz;
    vNormalEye = uNormalView * aNormal;
    vColour = aColour;
    gl_Position = uProjection * p;
}
