#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/PolylineTypes.h"

// Polylines relative to the eye (world axes: a model's path) or, with kScreen, quads already in
// clip space (labels, pins).

layout(constant_id = kPolylineSpecScreen) const bool kScreen = false;

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };

layout(location = kPolylineInputPosition) in vec4 inPosition;
layout(location = kPolylineInputColor) in vec4 inColor;

layout(location = 0) out vec4 vColor;

void main() {
    vColor = inColor;
    // A path on the ground would fight the terrain for depth: pull it 0.3 % towards the eye.
    gl_Position = kScreen ? inPosition : frame.projection * frame.viewRotation * vec4(inPosition.xyz * 0.997, 1.0);
}
