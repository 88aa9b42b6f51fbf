#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/VectorTypes.h"

// One point at altitude: a square of its size (and a pixel for the antialiasing) around its
// projection, facing the screen, or its icon `sizePx` high and `aspect` times as wide, both
// scaled with the camera's range when the style says so. A point behind the eye is dropped. A
// moving point is drawn where its glide has brought it by now. Its depth is pulled towards the
// eye by its size, so that the ground it stands on does not cut it.

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(push_constant) uniform PushBlock { VectorMeshPush pc; };

layout(location = kMarkerInputPosition) in vec3 inPosition;
layout(location = kMarkerInputColor) in vec4 inColor;
layout(location = kMarkerInputSize) in float inSize;
layout(location = kMarkerInputFeature) in uint inFeature;
layout(location = kMarkerInputIcon) in uint inIcon;
layout(location = kMarkerInputAspect) in float inAspect;
layout(location = kMarkerInputScale) in vec3 inScale;
layout(location = kMarkerInputFrom) in vec3 inFrom;
layout(location = kMarkerInputGlide) in vec2 inGlide;

layout(location = 0) out vec2 vPixel;   // pixels from the centre
layout(location = 1) flat out float vRadius;
layout(location = 2) flat out vec4 vColor;
layout(location = 3) out vec2 vUv;      // across an icon's quad, 0 to 1 from its top left
layout(location = 4) flat out uint vIcon;
layout(location = 5) flat out float vAspect;

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
    // A moving point glides from `inFrom` to its place, at a constant speed (MarkerMotion.h).
    float along = inGlide.y > inGlide.x ? clamp((pc.glideNow - inGlide.x) / (inGlide.y - inGlide.x), 0.0, 1.0) : 1.0;
    vec3 position = mix(inFrom, inPosition, along);
    vec4 p = frame.projection * frame.viewRotation * vec4(position + pc.originFromEye, 1.0);
    if (p.w <= 0.0) {
        gl_Position = vec4(2.0, 2.0, 0.5, 1.0);
        return;
    }
    bool highlighted = pc.highlight != 0u && inFeature == pc.highlight;
    // Scaled with the camera's range as the drape scales its icons (FeatureStyle::iconSizeAt).
    float size = inSize;
    if (inScale.y > inScale.x) {
        float range = length(position + pc.originFromEye);
        size *= 1.0 + clamp((range - inScale.x) / (inScale.y - inScale.x), 0.0, 1.0) * (inScale.z - 1.0);
    }
    float radius = 0.5 * (size + (highlighted ? 6.0 : 0.0));
    vec2 corner = kCorners[gl_VertexIndex];
    // An icon covers its quad exactly (its own alpha is its edge); a disk gets a pixel more.
    vec2 extent = inIcon != 0u ? vec2(radius * inAspect, radius) : vec2(radius + 1.0);
    vec2 offset = corner * extent;
    gl_Position = p + vec4(offset / (0.5 * frame.viewportSize) * p.w, 0.0, 0.0);
    // Its depth is that of the front of a ball of its size: a point on the ground (or gliding
    // along a chord a little under it) is not cut by the ground it stands on.
    vec3 fromEye = position + pc.originFromEye;
    float distance = length(fromEye);
    float metresPerPixel = 2.0 * distance / (abs(frame.projection[1][1]) * frame.viewportSize.y);
    float pull = min(max(extent.x, extent.y) * metresPerPixel, 0.5 * distance);
    vec4 front = frame.projection * frame.viewRotation * vec4(fromEye * (1.0 - pull / distance), 1.0);
    gl_Position.z = front.z / front.w * p.w;
    vPixel = offset;
    vRadius = radius;
    vColor = highlighted && inIcon == 0u ? vec4(1.0, 0.95, 0.1, 1.0) : inColor;
    vUv = 0.5 * corner + 0.5;
    vIcon = inIcon;
    vAspect = inAspect;
}
