#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FmvTypes.h"
#include "shared/FrameUniforms.h"

// The video frame projected onto the scene: each pixel's position from the scene depth
// (relative to the eye), seen from the sensor: inside its field of view and not hidden from it
// (its distance along the boresight no more than the sensor's distance map says, plus a bias),
// it takes the frame's colour at the given opacity. Output: premultiplied linear colour. Only
// the screen rectangle the sensor's view can cover (fu.rectOrigin, fu.rectSize, from the CPU)
// is dispatched, and pixels outside the convex polygon within it (fu.hull) stop before reading
// anything.

layout(local_size_x = kFmvGroupSize, local_size_y = kFmvGroupSize) in;

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(set = kFmvSet, binding = kFmvBindingUniforms) uniform FmvBlock { FmvUniforms fu; };
layout(set = kFmvSet, binding = kFmvBindingSceneDepth) uniform sampler2D sceneDepth;
layout(set = kFmvSet, binding = kFmvBindingVideoFrame) uniform sampler2D videoFrame;
layout(set = kFmvSet, binding = kFmvBindingDistanceMap) uniform sampler2D distanceMap;
layout(set = kFmvSet, binding = kFmvBindingDecal, rgba16f) uniform writeonly image2D decal;

#include "fmv/FmvCommon.glsl"

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy) + ivec2(fu.rectOrigin);
    ivec2 end = min(ivec2(fu.rectOrigin + fu.rectSize), imageSize(decal));
    if (px.x >= end.x || px.y >= end.y) return;
    vec4 outColor = vec4(0.0);
    vec2 centre = vec2(px) + 0.5;
    bool inside = true;
    for (uint i = 0u; i < fu.hullEdges; ++i) inside = inside && dot(fu.hull[i].xy, centre) + fu.hull[i].z >= 0.0;
    float depth = inside ? texelFetch(sceneDepth, px, 0).r : 0.0;
    if (depth > 0.0 && fu.frameShown != 0u) {
        vec2 ndc = (vec2(px) + 0.5) * frame.invViewportSize * 2.0 - 1.0;
        vec4 w = frame.clipToWorldDir * vec4(ndc, depth, 1.0);
        vec3 q = w.xyz / w.w - fu.originFromEye;   // relative to O
        vec3 s = sensorImage(q);
        if (s.z > 0.0 && all(lessThanEqual(abs(s.xy), vec2(1.0)))) {
            vec2 mapUv = s.xy / fu.mapFovScale * 0.5 + 0.5;
            float seen = textureLod(distanceMap, mapUv, 0.0).r;
            float bias = fu.occlusionBias + fu.occlusionBiasPerMetre * s.z;
            if (s.z <= seen + bias) {
                vec3 c = textureLod(videoFrame, s.xy * 0.5 + 0.5, 0.0).rgb;   // sRGB view: linear
                outColor = vec4(c * fu.opacity, fu.opacity);
            }
        }
    }
    imageStore(decal, px, outColor);
}
