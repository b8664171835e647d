#version 330 core
// The ground's look: a floor a little lighter than the background that fades into it towards
// the square's edge, darkened under the model by a soft contact shadow (a rounded square the
// size of the model's footprint, blurred): a cue for where the model stands, not a cast shadow.
in vec2 vGround;

uniform vec2 uCentre;             // m, world x and y of the square's centre
uniform float uHalfSize;          // m, half the square's side
uniform vec2 uFootprintHalf;      // m, half the model's extent in x and y
uniform vec3 uBackgroundSrgb;     // sRGB 0..1, what the floor fades into
uniform vec3 uFloorSrgb;          // sRGB 0..1

out vec4 fragColour;

void main() {
    float r = length(vGround - uCentre) / uHalfSize;
    float fade = 1.0 - smoothstep(0.35, 1.0, r);
    // A superellipse (4-norm): round for a round footprint's box, square-ish under a box.
    vec2 q = abs(vGround - uCentre) / max(uFootprintHalf, vec2(1e-6));
    q = q * q;
    float d = sqrt(sqrt(dot(q, q)));
    float shadow = 0.7 * (1.0 - smoothstep(0.75, 1.6, d));
    // Blended in sRGB space, as the background it fades into is stored.
    vec3 floorColour = uFloorSrgb * (1.0 - shadow);
    fragColour = vec4(mix(uBackgroundSrgb, floorColour, fade), 1.0);
}
