#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"

// A simple analytic sky: glow that falls off with the height of the ray's closest approach to
// the Earth, lit by the sun. Float ECEF is fine here: it shades, it places no geometry.
layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };

layout(location = 0) in vec2 vNdc;
layout(location = 0) out vec4 outColor;

const float kScaleHeight = 8500.0 * 4.0;    // metres; broader than the real one so it reads from space

void main() {
    vec4 far = frame.clipToWorldDir * vec4(vNdc, 1.0, 1.0);
    vec3 dir = normalize(far.xyz / far.w);
    // Work in units of the equatorial radius, with the polar axis stretched to a sphere.
    vec3 stretch = vec3(1.0, 1.0, frame.equatorialRadius / frame.polarRadius);
    vec3 eye = frame.eyeEcef * stretch / frame.equatorialRadius;
    vec3 d = normalize(dir * stretch);
    float t = max(-dot(eye, d), 0.0);
    vec3 closest = eye + d * t;
    float altitude = (length(closest) - 1.0) * frame.equatorialRadius;
    float glow = exp(-max(altitude, 0.0) / kScaleHeight);

    bool sun = frame.sunLighting > 0.5;
    float lit = sun ? smoothstep(-0.25, 0.35, dot(normalize(closest), frame.sunDirection)) : 1.0;
    vec3 sky = vec3(0.28, 0.52, 1.00) * glow * lit;
    // Looking up from inside the atmosphere the sky is bright; looking out from space it is a rim.
    outColor = vec4(frame.background + sky, 1.0);
}
