#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/EarthTypes.h"

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(push_constant) uniform PushBlock { EarthPush pc; };

layout(location = kEarthInputPosition) in vec3 inPosition;   // relative to the patch origin
layout(location = kEarthInputNormal) in vec3 inNormal;
layout(location = kEarthInputLonLat) in vec2 inLonLat;

layout(location = 0) out vec3 vNormal;
layout(location = 1) out vec2 vLonLat;
layout(location = 2) out vec3 vFromEye;    // world axes, relative to the eye: small numbers only

void main() {
    gl_Position = pc.modelViewProj * vec4(inPosition, 1.0);
    vNormal = inNormal;
    vLonLat = inLonLat;
    vFromEye = pc.originFromEye + inPosition;
}
