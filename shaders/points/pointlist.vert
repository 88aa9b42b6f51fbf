#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/PointTypes.h"

// The fallback without 64-bit atomics (and the baseline the compute path is measured
// against): one vertex a point, drawn as a point list, one draw a node.

layout(set = 1, binding = 0) uniform PointBlock { PointUniforms pu; };
layout(set = 1, binding = 1, std430) readonly buffer Positions { float positions[]; };
layout(set = 1, binding = 2, std430) readonly buffer Attributes { uvec2 attributes[]; };
layout(set = 1, binding = 4, std430) readonly buffer Nodes { vec4 nodeCentres[]; };
layout(push_constant) uniform Push { uint node; } push;

layout(location = 0) out vec3 color;

#include "points/PointColor.glsl"

void main() {
    uint i = uint(gl_VertexIndex);
    vec3 p = nodeCentres[push.node].xyz + vec3(positions[3u * i], positions[3u * i + 1u], positions[3u * i + 2u]);
    gl_Position = pu.viewProj * vec4(p, 1.0);
    gl_PointSize = pu.edl.w;
    color = pointColor(attributes[i]);
}
