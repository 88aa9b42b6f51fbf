#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/VectorTypes.h"

// One segment of a line at altitude (six vertices, two triangles): its ends relative to the eye
// (the chunk's origin minus the eye was taken in double on the CPU), projected, and the quad
// widened across the segment on the screen by half the width and a pixel for the antialiasing,
// and lengthened by as much at both ends (square caps that join the next segment). An end
// behind the eye is first moved along the segment to just in front of it. A dashed line's
// dashes are laid out in metres along the line, at about their pixel sizes.

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(push_constant) uniform PushBlock { VectorMeshPush pc; };

layout(location = kSegmentInputA) in vec3 inA;
layout(location = kSegmentInputColor) in vec4 inColor;
layout(location = kSegmentInputB) in vec3 inB;
layout(location = kSegmentInputWidth) in float inWidth;
layout(location = kSegmentInputFeature) in uint inFeature;
layout(location = kSegmentInputStart) in float inStart;
layout(location = kSegmentInputDash) in vec2 inDash;

layout(location = 0) out float vAcross;   // pixels from the segment's axis
layout(location = 1) flat out float vHalfWidth;
layout(location = 2) flat out vec4 vColor;
layout(location = 3) out float vAlong;          // metres along the line
layout(location = 4) flat out float vPeriod;    // of the dashes (m), 0: solid
layout(location = 5) flat out float vOn;        // the dashes' share of it

// x: 0 at A, 1 at B; y: the side.
const vec2 kCorners[6] = vec2[](vec2(0, -1), vec2(1, -1), vec2(1, 1), vec2(0, -1), vec2(1, 1), vec2(0, 1));
const float kInFront = 1e-3;   // clip w (metres in front of the eye) an end is moved to

void main() {
    vec2 corner = kCorners[gl_VertexIndex];
    mat4 viewProj = frame.projection * frame.viewRotation;
    vec4 a = viewProj * vec4(inA + pc.originFromEye, 1.0);
    vec4 b = viewProj * vec4(inB + pc.originFromEye, 1.0);
    // Dashes: the pattern in metres at the scale of the segment's middle, in steps of two (so
    // that it stays put as the camera moves, and changes only when the scale halves or doubles).
    float pixelsPerMetre = abs(frame.projection[1][1]) * 0.5 * frame.viewportSize.y / max(0.5 * (a.w + b.w), kInFront);
    float periodPx = inDash.x + inDash.y;
    vPeriod = inDash.x > 0.0 && inDash.y > 0.0 ? exp2(round(log2(periodPx / pixelsPerMetre))) : 0.0;
    vOn = periodPx > 0.0 ? inDash.x / periodPx : 1.0;
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
    // The caps reach past the ends by `reach` pixels: as many metres less or more along.
    float lengthM = length(inB - inA);
    vAlong = inStart + (corner.x < 0.5 ? -reach / pixelsPerMetre : lengthM + reach / pixelsPerMetre);
    vHalfWidth = halfWidth;
    vColor = highlighted ? vec4(1.0, 0.95, 0.1, 1.0) : inColor;
}
