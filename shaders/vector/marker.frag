#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/VectorTypes.h"

// A disk in the point's colour with a dark rim of 1.5 pixels, antialiased at its edge (as the
// drape paints its markers). Colours come in sRGB and leave linear and premultiplied.

layout(location = 0) in vec2 vPixel;
layout(location = 1) flat in float vRadius;
layout(location = 2) flat in vec4 vColor;

layout(location = 0) out vec4 outColor;

vec3 srgbToLinear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

void main() {
    float r = length(vPixel);
    float coverage = clamp(vRadius + 0.5 - r, 0.0, 1.0);
    if (coverage <= 0.0) discard;
    float inner = clamp(vRadius - 1.5 + 0.5 - r, 0.0, 1.0);
    vec3 color = mix(vec3(0.05), srgbToLinear(vColor.rgb), inner);
    float alpha = coverage * vColor.a;
    outColor = vec4(color * alpha, alpha);
}
