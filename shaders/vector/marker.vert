#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/VectorTypes.h"

// One point at altitude: a square of its size (and a pixel for the antialiasing) around its
// projection, facing the screen. A point behind the eye is dropped.

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(push_constant) uniform PushBlock { VectorMeshPush pc; };

layout(location = kMarkerInputPosition) in vec3 inPosition;
layout(location = kMarkerInputColor) in vec4 inColor;
layout(location = kMarkerInputSize) in float inSize;
layout(location = kMarkerInputFeature) in uint inFeature;

layout(location = 0) out vec2 vPixel;   // pixels from the centre
layout(location = 1) flat out float vRadius;
layout(location = 2) flat out vec4 vColor;

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
    vec4 p = frame.projection * frame.viewRotation * vec4(inPosition + pc.originFromEye, 1.0);
    if (p.w <= 0.0) {
        gl_Position = vec4(2.0, 2.0, 0.5, 1.0);
        return;
    }
    bool highlighted = pc.highlight != 0u && inFeature == pc.highlight;
    float radius = 0.5 * (inSize + (highlighted ? 6.0 : 0.0));
    vec2 offset = kCorners[gl_VertexIndex] * (radius + 1.0);
    gl_Position = p + vec4(offset / (0.5 * frame.viewportSize) * p.w, 0.0, 0.0);
    vPixel = offset;
    vRadius = radius;
    vColor = highlighted ? vec4(1.0, 0.95, 0.1, 1.0) : inColor;
}
