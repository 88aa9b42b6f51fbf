#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/PointTypes.h"

// The fallback without 64-bit atomics (and the baseline the compute path is measured
// against): one vertex a point, drawn as a point list, one draw a node.

layout(set = kPointSet, binding = kPointBindingUniforms) uniform PointBlock { PointUniforms pu; };
layout(set = kPointSet, binding = kPointBindingWords, std430) readonly buffer Words { uint words[]; };
layout(set = kPointSet, binding = kPointBindingAttributes, std430) readonly buffer Attributes { uvec2 attributes[]; };
layout(set = kPointSet, binding = kPointBindingNodes, std430) readonly buffer Nodes { PointNode nodes[]; };
layout(push_constant) uniform PushBlock { PointPush push; };

layout(location = 0) out vec4 color;   // premultiplied by the cloud's opacity

#include "points/PointColor.glsl"
#include "points/PointData.glsl"

void main() {
    PointNode node = nodes[push.node];
    uint local = uint(gl_VertexIndex);   // drawn from 0: the point within its node
    vec3 p = pointPosition(node, local);
    gl_Position = pu.viewProj * vec4(p, 1.0);
    gl_PointSize = pu.adaptivePixels > 0.0 ? clamp(2.0 * floor(adaptiveRadius(node, p)) + 1.0, pu.pointSizePx, float(2 * kPointMaxAdaptiveRadius + 1))
                                           : pu.pointSizePx;
    color = vec4(pointColor(attributes[node.firstAttribute + local]), 1.0) * pu.opacity;
}
