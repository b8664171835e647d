#version 330 core
// Matcap shading (Bremer's figure 1): the colour is a function of the eye-space normal alone,
// as if a lit sphere's image were looked up at (n.x, n.y). The sphere is computed here rather
// than read from an image: a glossy grey-clay ball lit from the upper left with a soft rim.
// Painted colours tint the diffuse part.
in vec3 vPositionEye;
in vec3 vNormalEye;
in vec4 vColour;

uniform vec3 uClaySrgb;       // the unpainted clay's colour, sRGB 0..1
uniform int uOrthographic;    // 1: the view direction is -Z everywhere

out vec4 fragColour;

vec3 toLinear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c));
}

vec3 toSrgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

// The matcap sphere at uv in [-1, 1]^2 (its normal is (uv, sqrt(1 - |uv|^2))).
vec3 matcap(vec2 uv, vec3 albedo) {
    vec3 s = vec3(uv, sqrt(max(1.0 - dot(uv, uv), 0.0)));
    vec3 l = normalize(vec3(-0.4, 0.55, 0.75));
    float d = max(dot(s, l), 0.0);
    vec3 base = albedo * (0.12 + 0.95 * d * d * (3.0 - 2.0 * d));
    float highlight = pow(max(dot(reflect(-l, s), vec3(0.0, 0.0, 1.0)), 0.0), 40.0) * 0.35;
    float rim = pow(1.0 - s.z, 2.5) * 0.35;
    return base + vec3(highlight) + rim * vec3(0.75, 0.80, 0.90);
}

void main() {
    vec3 n = normalize(vNormalEye);
    if (!gl_FrontFacing) n = -n;
    // In perspective, the normal is taken relative to the ray through the pixel so the shading
    // does not slide towards the edges of the image.
    if (uOrthographic == 0) {
        vec3 v = normalize(-vPositionEye);
        vec3 x = normalize(cross(vec3(0.0, 1.0, 0.0), v));
        vec3 y = cross(v, x);
        n = vec3(dot(n, x), dot(n, y), dot(n, v));
    }
    vec3 albedo = toLinear(mix(uClaySrgb, vColour.rgb, vColour.a));
    fragColour = vec4(toSrgb(matcap(n.xy, albedo)), 1.0);
}
