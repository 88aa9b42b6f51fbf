#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/VectorTypes.h"

// A glyph from its signed distance field: the text inside the outline (vEdges.x), or, in the
// halo pipeline, the halo out to vEdges.y. Each edge is smoothed over about a screen pixel:
// fwidth gives the field's change per pixel at the size and angle the glyph is drawn at.
// Colours come in sRGB and leave linear and premultiplied (the target is sRGB; blending "over").

layout(constant_id = kLabelSpecHalo) const bool kHalo = false;

layout(set = kLabelSet, binding = kLabelBindingAtlas) uniform sampler2D atlas;

layout(location = 0) in vec2 vUv;
layout(location = 1) flat in vec2 vEdges;
layout(location = 2) flat in vec4 vColor;
layout(location = 3) flat in vec4 vHalo;

layout(location = 0) out vec4 outColor;

vec3 srgbToLinear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

void main() {
    float value = texture(atlas, vUv).r;
    // Half a pixel of the field either side of the edge; never zero (the field is flat where it
    // saturates, far outside the outline).
    float halfPixel = max(0.5 * fwidth(value), 1.0 / 1024.0);
    float edge = kHalo ? vEdges.y : vEdges.x;
    float coverage = smoothstep(edge - halfPixel, edge + halfPixel, value);
    vec4 color = kHalo ? vHalo : vColor;
    float alpha = color.a * coverage;
    if (alpha <= 0.0) discard;
    outColor = vec4(srgbToLinear(color.rgb) * alpha, alpha);
}
