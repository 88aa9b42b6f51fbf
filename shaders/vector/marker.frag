#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/VectorTypes.h"

// A disk in the point's colour with a dark rim of 1.5 pixels, antialiased at its edge (as the
// drape paints its markers), or the point's icon from the atlas (its cell holds the icon fitted
// and centred), at the point's opacity. Colours come in sRGB and leave linear and premultiplied.

layout(set = kMeshSet, binding = kMeshBindingIcons) uniform sampler2D icons;

layout(location = 0) in vec2 vPixel;
layout(location = 1) flat in float vRadius;
layout(location = 2) flat in vec4 vColor;
layout(location = 3) in vec2 vUv;
layout(location = 4) flat in uint vIcon;
layout(location = 5) flat in float vAspect;

layout(location = 0) out vec4 outColor;

vec3 srgbToLinear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

void main() {
    if (vIcon != 0u) {
        uint cell = vIcon - 1u;
        // The icon's rectangle within its square cell: the whole width or the whole height.
        vec2 size = vAspect >= 1.0 ? vec2(1.0, 1.0 / vAspect) : vec2(vAspect, 1.0);
        vec2 inCell = 0.5 * (1.0 - size) + vUv * size;
        vec2 uv = (vec2(float(cell % kMeshIconCells), float(cell / kMeshIconCells)) + inCell) / float(kMeshIconCells);
        vec4 c = texture(icons, uv);   // the atlas is sRGB: linear here
        float alpha = c.a * vColor.a;
        if (alpha <= 0.0) discard;
        outColor = vec4(c.rgb * alpha, alpha);
        return;
    }
    float r = length(vPixel);
    float coverage = clamp(vRadius + 0.5 - r, 0.0, 1.0);
    if (coverage <= 0.0) discard;
    float inner = clamp(vRadius - 1.5 + 0.5 - r, 0.0, 1.0);
    vec3 color = mix(vec3(0.05), srgbToLinear(vColor.rgb), inner);
    float alpha = coverage * vColor.a;
    outColor = vec4(color * alpha, alpha);
}
