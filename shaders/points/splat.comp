#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_ARB_gpu_shader_int64 : require
#extension GL_EXT_control_flow_attributes : require
#include "shared/PointTypes.h"

// Compute rasterisation of points: each point is projected (positions relative to its node's
// centre, quantised or float, the node's centre relative to the eye: small numbers near the
// eye), tested against the scene's depth, and written as (depth bits << 32 | sRGB colour) with
// a 64-bit atomicMax into a screen buffer: with reversed Z the largest depth is the nearest, and
// among equal depths the largest colour value wins, so the image never depends on the order of
// the writes. The colour, not the point's index, goes in the low bits: the resolve then reads
// nothing but the screen, and the nodes' data can be in pages (one dispatch per page), as
// maxStorageBufferRange may be smaller than the resident data.

layout(local_size_x = kPointGroupSize) in;

// Splat radius in pixels: 0 writes one pixel; r covers the disc of radius r + 0.5.
layout(constant_id = kPointSpecRadius) const int kRadius = 0;
// Level-aware sizes: each point's radius from the level drawn at its place (at least kRadius, at
// most kPointMaxAdaptiveRadius).
layout(constant_id = kPointSpecAdaptive) const bool kAdaptive = false;

// The batches of one position format: [first, first + dispatched groups).
layout(push_constant) uniform PushBlock { PointPush push; };

layout(set = kPointSet, binding = kPointBindingUniforms) uniform PointBlock { PointUniforms pu; };
layout(set = kPointSet, binding = kPointBindingWords, std430) readonly buffer Words { uint words[]; };
layout(set = kPointSet, binding = kPointBindingAttributes, std430) readonly buffer Attributes { uvec2 attributes[]; };
layout(set = kPointSet, binding = kPointBindingBatches, std430) readonly buffer Batches { PointBatch batches[]; };
layout(set = kPointSet, binding = kPointBindingNodes, std430) readonly buffer Nodes { PointNode nodes[]; };
layout(set = kPointSet, binding = kPointBindingScreen, std430) buffer Screen { uint64_t screen[]; };
layout(set = kPointSet, binding = kPointBindingSceneDepth) uniform sampler2D sceneDepth;

#include "points/PointColor.glsl"
#include "points/PointData.glsl"

void main() {
    PointBatch batch = batches[push.firstBatch + gl_WorkGroupID.x];
    PointNode node = nodes[batch.node];
    ivec2 size = ivec2(pu.screenSize);
    for (uint k = 0u; k < kPointsPerInvocation; ++k) {
        uint local = k * kPointGroupSize + gl_LocalInvocationID.x;
        if (local >= batch.count) break;
        local += batch.first;   // within the node
        vec3 p = pointPosition(node, local);
        vec4 clip = pu.viewProj * vec4(p, 1.0);
        if (clip.w <= 0.0) continue;   // behind the eye
        float depth = clip.z / clip.w;
        if (depth > 1.0) continue;     // nearer than the near plane
        vec2 pixel = (clip.xy / clip.w * 0.5 + 0.5) * pu.screenSize;
        ivec2 px = ivec2(floor(pixel));
        const int reach = kAdaptive ? kPointMaxAdaptiveRadius : kRadius;
        if (px.x < -reach || px.y < -reach || px.x >= size.x + reach || px.y >= size.y + reach) continue;
        int radius = kRadius;
        if (kAdaptive) radius = clamp(int(adaptiveRadius(node, p)), kRadius, kPointMaxAdaptiveRadius);
        if (kAdaptive && radius > kRadius) {
            uint64_t packed = (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(pointColorPacked(attributes[node.firstAttribute + local]));
            for (int dy = -radius; dy <= radius; ++dy)
                for (int dx = -radius; dx <= radius; ++dx) {
                    if (dx * dx + dy * dy > radius * radius + radius) continue;   // a disc
                    ivec2 q = px + ivec2(dx, dy);
                    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
                    if (depth < texelFetch(sceneDepth, q, 0).r) continue;
                    atomicMax(screen[q.y * size.x + q.x], packed);
                }
            continue;
        }
        if (kRadius == 0) {
            if (depth < texelFetch(sceneDepth, px, 0).r) continue;   // behind the opaque scene
            uint color = pointColorPacked(attributes[node.firstAttribute + local]);
            atomicMax(screen[px.y * size.x + px.x], (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(color));
            continue;
        }
        uint64_t packed = (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(pointColorPacked(attributes[node.firstAttribute + local]));
        [[unroll]] for (int dy = -kRadius; dy <= kRadius; ++dy)
            [[unroll]] for (int dx = -kRadius; dx <= kRadius; ++dx) {
                if (dx * dx + dy * dy > kRadius * kRadius + kRadius) continue;   // a disc
                ivec2 q = px + ivec2(dx, dy);
                if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
                if (depth < texelFetch(sceneDepth, q, 0).r) continue;
                atomicMax(screen[q.y * size.x + q.x], packed);
            }
    }
}
