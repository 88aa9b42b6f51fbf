#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/VectorTypes.h"

// The fill colour lit by the sun (or a headlight when the scene has no sun lighting), with a
// sky ambient term so that walls turned away stay readable; both faces of a two-sided surface
// are lit. The picked feature turns the highlight's yellow (the drape's, VectorDrape.cpp).
// Alpha is the vertex colour's (a surface's fillOpacity), premultiplied.

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };

layout(location = 0) in vec3 vNormal;
layout(location = 1) in vec3 vFromEye;
layout(location = 2) flat in vec4 vColor;
layout(location = 3) flat in uint vHighlighted;

layout(location = 0) out vec4 outColor;

vec3 srgbToLinear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

void main() {
    vec3 base = srgbToLinear(vHighlighted != 0u ? vec3(1.0, 0.95, 0.1) : vColor.rgb);
    vec3 n = normalize(vNormal);
    vec3 toEye = normalize(-vFromEye);
    if (dot(n, toEye) < 0.0) n = -n;
    bool sun = frame.sunLighting > 0.5;
    vec3 toLight = sun ? frame.sunDirection : toEye;
    float diffuse = max(dot(n, toLight), 0.0);
    float ambient = sun ? 0.25 : 0.3;
    // Premultiplied: solids are opaque, a translucent surface blends "over".
    float alpha = vHighlighted != 0u ? 1.0 : vColor.a;
    outColor = vec4(base * (ambient + (1.0 - ambient) * diffuse) * alpha, alpha);
}
