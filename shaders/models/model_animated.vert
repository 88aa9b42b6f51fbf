#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/ModelTypes.h"

// A glTF vertex of an animated model (layers/models/GltfAnimation.h): morphed by its node's
// weights, then placed by its skin's joint matrices or its node's matrix, all read from the
// pose block of its instance; then the instance's model-to-eye transform as in model.vert.
// Static models use model.vert (no pose, no second vertex stream).

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(set = 1, binding = 0, std430) readonly buffer Instances { ModelInstance instances[]; };
layout(set = 1, binding = 2, std430) readonly buffer Poses { vec4 poses[]; };
layout(set = 1, binding = 3, std430) readonly buffer Morphs { float morphDeltas[]; };
layout(push_constant) uniform PushBlock { ModelPush pc; };

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 3) in vec4 inColor;
layout(location = 4) in uvec4 inJoints;
layout(location = 5) in vec4 inWeights;

layout(location = 0) out vec3 vNormal;
layout(location = 1) out vec2 vUv;
layout(location = 2) out vec4 vColor;
layout(location = 3) out vec3 vFromEye;

mat4 poseMatrix(uint at) { return mat4(poses[at], poses[at + 1], poses[at + 2], poses[at + 3]); }

float poseFloat(uint at) { return poses[at >> 2][at & 3u]; }

void main() {
    ModelInstance inst = instances[gl_InstanceIndex];
    uint pose = inst.pose.x;
    vec3 position = inPosition;
    vec3 normal = inNormal;
    // Morph targets: (vertex, target) pairs of 6 floats; gl_VertexIndex includes the draw's
    // vertex offset, which pc.morph.x has taken out (modulo 2^32).
    uint targets = pc.ids.z;
    for (uint k = 0u; k < targets; ++k) {
        float w = poseFloat(pose * 4u + pc.ids.w + k);
        if (w == 0.0) continue;
        uint d = (pc.morph.x + uint(gl_VertexIndex) * targets + k) * 6u;
        position += w * vec3(morphDeltas[d], morphDeltas[d + 1u], morphDeltas[d + 2u]);
        normal += w * vec3(morphDeltas[d + 3u], morphDeltas[d + 4u], morphDeltas[d + 5u]);
    }
    mat4 m;
    if (pc.ids.y != kModelPoseNone) {
        uint joints = pose + pc.ids.y;
        m = inWeights.x * poseMatrix(joints + 4u * inJoints.x) + inWeights.y * poseMatrix(joints + 4u * inJoints.y) +
            inWeights.z * poseMatrix(joints + 4u * inJoints.z) + inWeights.w * poseMatrix(joints + 4u * inJoints.w);
    } else {
        m = poseMatrix(pose + pc.ids.x);
    }
    // The cofactor matrix is the inverse transpose times the determinant: right for normals
    // under any scale (the sign is fixed in the fragment shader, which lights both faces).
    mat3 a = mat3(m);
    mat3 cofactor = mat3(cross(a[1], a[2]), cross(a[2], a[0]), cross(a[0], a[1]));
    vec4 p = inst.modelToEye * (m * vec4(position, 1.0));
    vNormal = mat3(inst.modelToEye) * (cofactor * normal);
    vUv = inUv;
    vColor = inColor * vec4(inst.tint.rgb, 1.0);
    vFromEye = p.xyz;
    gl_Position = frame.projection * frame.viewRotation * p;
}
