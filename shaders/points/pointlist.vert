#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/PointTypes.h"

// The fallback without 64-bit atomics (and the baseline the compute path is measured
// against): one vertex a point, drawn as a point list, one draw a node.

layout(set = 1, binding = 0) uniform PointBlock { PointUniforms pu; };
layout(set = 1, binding = 1, std430) readonly buffer Words { uint words[]; };
layout(set = 1, binding = 2, std430) readonly buffer Attributes { uvec2 attributes[]; };
layout(set = 1, binding = 4, std430) readonly buffer Nodes { PointNode nodes[]; };
layout(push_constant) uniform Push { uint node; uint firstBatch; } push;

layout(location = 0) out vec4 color;   // premultiplied by the cloud's opacity

#include "points/PointColor.glsl"
#include "points/PointData.glsl"

void main() {
    PointNode node = nodes[push.node];
    uint local = uint(gl_VertexIndex);   // drawn from 0: the point within its node
    gl_Position = pu.viewProj * vec4(pointPosition(node, local), 1.0);
    gl_PointSize = pu.edl.w;
    color = vec4(pointColor(attributes[node.data.x + local]), 1.0) * pu.colorInfo.x;
}
