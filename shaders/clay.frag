#version 330 core
// Lit clay: the surface shaded by clay_shading.frag (linked with it).
in vec3 vPositionEye;
in vec3 vNormalEye;
in vec4 vColour;

uniform int uOrthographic;  // 1: the view direction is -Z everywhere

out vec4 fragColour;

vec3 shadeClay(vec3 n, vec3 v, vec4 colour);  // clay_shading.frag

void main() {
    vec3 n = normalize(vNormalEye);
    // Back faces (seen through an open mesh) are lit as the inside of the shell.
    if (!gl_FrontFacing) n = -n;
    vec3 v = uOrthographic != 0 ? vec3(0.0, 0.0, 1.0) : normalize(-vPositionEye);
    fragColour = vec4(shadeClay(n, v, vColour), 1.0);
}
