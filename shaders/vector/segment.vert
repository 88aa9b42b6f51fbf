#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/VectorTypes.h"

// One segment of a line at altitude (six vertices, two triangles): its ends relative to the eye
// (the chunk's origin minus the eye was taken in double on the CPU), projected, and the quad
// widened across the segment on the screen by half the width and a pixel for the antialiasing,
// and lengthened by as much at both ends (square caps that join the next segment). An end
// behind the eye is first moved along the segment to just in front of it.

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(push_constant) uniform PushBlock { VectorMeshPush pc; };

layout(location = kSegmentInputA) in vec3 inA;
layout(location = kSegmentInputColor) in vec4 inColor;
layout(location = kSegmentInputB) in vec3 inB;
layout(location = kSegmentInputWidth) in float inWidth;
layout(location = kSegmentInputFeature) in uint inFeature;

layout(location = 0) out float vAcross;   // pixels from the segment's axis
layout(location = 1) flat out float vHalfWidth;
layout(location = 2) flat out vec4 vColor;

// x: 0 at A, 1 at B; y: the side.
const vec2 kCorners[6] = vec2[](vec2(0, -1), vec2(1, -1), vec2(1, 1), vec2(0, -1), vec2(1, 1), vec2(0, 1));
const float kInFront = 1e-3;   // clip w (metres in front of the eye) an end is moved to

void main() {
    vec2 corner = kCorners[gl_VertexIndex];
    mat4 viewProj = frame.projection * frame.viewRotation;
    vec4 a = viewProj * vec4(inA + pc.originFromEye, 1.0);
    vec4 b = viewProj * vec4(inB + pc.originFromEye, 1.0);
    if (a.w < kInFront && b.w < kInFront) {
        gl_Position = vec4(2.0, 2.0, 0.5, 1.0);   // behind the eye: a degenerate quad off screen
        return;
    }
    if (a.w < kInFront) a = mix(a, b, (kInFront - a.w) / (b.w - a.w));
    if (b.w < kInFront) b = mix(b, a, (kInFront - b.w) / (a.w - b.w));
    vec2 halfViewport = 0.5 * frame.viewportSize;
    vec2 sa = a.xy / a.w * halfViewport, sb = b.xy / b.w * halfViewport;
    vec2 along = sb - sa;
    along = dot(along, along) > 1e-12 ? normalize(along) : vec2(1.0, 0.0);
    vec2 across = vec2(-along.y, along.x);
    bool highlighted = pc.highlight != 0u && inFeature == pc.highlight;
    float halfWidth = 0.5 * (inWidth + (highlighted ? 3.0 : 0.0));
    float reach = halfWidth + 1.0;
    vec4 end = corner.x < 0.5 ? a : b;
    vec2 offset = across * corner.y * reach + along * (corner.x < 0.5 ? -reach : reach);
    gl_Position = end + vec4(offset / halfViewport * end.w, 0.0, 0.0);
    vAcross = corner.y * reach;
    vHalfWidth = halfWidth;
    vColor = highlighted ? vec4(1.0, 0.95, 0.1, 1.0) : inColor;
}
