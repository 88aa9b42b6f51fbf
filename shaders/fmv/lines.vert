#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FmvTypes.h"
#include "shared/FrameUniforms.h"

// The footprint's outline (a line strip over the border rays' ground points, closed) or the
// sensor's frustum (a line list: the sensor to each corner's ground point), from the footprint
// buffer, drawn a little towards the eye so that the outline is not hidden in the ground.

layout(constant_id = kFmvSpecFrustum) const bool kFrustum = false;

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(set = kFmvSet, binding = kFmvBindingUniforms) uniform FmvBlock { FmvUniforms fu; };
layout(set = kFmvSet, binding = kFmvBindingFootprint, std430) readonly buffer Footprint { vec4 points[]; };

void main() {
    vec3 q;
    if (kFrustum) {
        uint corner = uint(gl_VertexIndex) / 2u;   // 0..3
        q = (gl_VertexIndex & 1) == 0 ? fu.sensor : points[corner * kFmvEdgeRays].xyz;
    } else {
        q = points[uint(gl_VertexIndex) % (4u * kFmvEdgeRays)].xyz;
    }
    vec3 p = (q + fu.originFromEye) * 0.997;   // relative to the eye, pulled towards it
    gl_Position = frame.projection * frame.viewRotation * vec4(p, 1.0);
}
