#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/VectorTypes.h"

// A segment's coverage from the distance to its axis (a one-pixel ramp at each edge), in its
// colour with its opacity; nothing in the gaps of a dashed line. Colours come in sRGB and leave linear and premultiplied.

layout(location = 0) in float vAcross;
layout(location = 1) flat in float vHalfWidth;
layout(location = 2) flat in vec4 vColor;
layout(location = 3) in float vAlong;
layout(location = 4) flat in float vPeriod;
layout(location = 5) flat in float vOn;

layout(location = 0) out vec4 outColor;

vec3 srgbToLinear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

void main() {
    if (vPeriod > 0.0 && fract(vAlong / vPeriod) > vOn) discard;   // a gap between dashes
    float coverage = clamp(vHalfWidth + 0.5 - abs(vAcross), 0.0, 1.0);
    float alpha = coverage * vColor.a;
    if (alpha <= 0.0) discard;
    outColor = vec4(srgbToLinear(vColor.rgb) * alpha, alpha);
}
