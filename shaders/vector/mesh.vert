#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/VectorTypes.h"

// A building's or a polygon's vertex: relative to its chunk's origin, which is relative to the
// eye (both small numbers: the origin minus the eye was taken in double on the CPU).

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(push_constant) uniform PushBlock { VectorMeshPush pc; };

layout(location = kMeshInputPosition) in vec3 inPosition;
layout(location = kMeshInputNormal) in vec4 inNormal;
layout(location = kMeshInputColor) in vec4 inColor;
layout(location = kMeshInputFeature) in uint inFeature;

layout(location = 0) out vec3 vNormal;
layout(location = 1) out vec3 vFromEye;
layout(location = 2) flat out vec4 vColor;
layout(location = 3) flat out uint vHighlighted;

void main() {
    vec3 p = inPosition + pc.originFromEye;
    vNormal = inNormal.xyz;
    vFromEye = p;
    vColor = inColor;
    vHighlighted = (pc.highlight != 0u && inFeature == pc.highlight) ? 1u : 0u;
    gl_Position = frame.projection * frame.viewRotation * vec4(p, 1.0);
}
