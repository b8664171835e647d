#version 330 core
// The lit clay's shading, linked into every program that lights clay (clay.frag, points.frag):
// Blinn-Phong with a warm key light, a cool fill and a rim term, plus a sky/ground hemisphere
// for ambient. Lights are fixed in eye space (a studio that turns with the camera), so every
// view of the model is lit alike. Shading is done in linear light and returned sRGB-encoded
// (the framebuffer is plain RGBA8).

uniform vec3 uClaySrgb;  // the unpainted clay's colour, sRGB 0..1

vec3 toLinear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c));
}

vec3 toSrgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

// One directional light: wrapped Lambert (soft terminator, as clay scatters a little) and a
// broad, weak Blinn-Phong highlight (clay is matte).
vec3 light(vec3 n, vec3 v, vec3 l, vec3 colour, vec3 albedo) {
    float wrap = 0.15;
    float diffuse = max((dot(n, l) + wrap) / (1.0 + wrap), 0.0);
    vec3 h = normalize(l + v);
    float specular = pow(max(dot(n, h), 0.0), 24.0) * 0.12 * step(0.0, dot(n, l));
    return colour * (albedo * diffuse + vec3(specular));
}

// The clay's sRGB colour at unit eye-space normal n, seen from unit direction v (towards the
// eye), painted with `colour` in proportion to its alpha (0: the clay colour).
vec3 shadeClay(vec3 n, vec3 v, vec4 colour) {
    vec3 albedo = toLinear(mix(uClaySrgb, colour.rgb, colour.a));
    vec3 c = vec3(0.0);
    c += light(n, v, normalize(vec3(-0.55, 0.6, 0.6)), vec3(1.00, 0.93, 0.82) * 1.15, albedo);  // key
    c += light(n, v, normalize(vec3(0.8, -0.15, 0.35)), vec3(0.75, 0.85, 1.00) * 0.18, albedo);  // fill
    vec3 sky = vec3(0.30, 0.32, 0.36), ground = vec3(0.15, 0.12, 0.10);
    c += albedo * mix(ground, sky, 0.5 + 0.5 * n.y) * 0.40;                                      // ambient
    float rim = pow(1.0 - max(dot(n, v), 0.0), 3.0);
    c += rim * vec3(0.14, 0.15, 0.18);                                                           // rim
    return toSrgb(c);
}
