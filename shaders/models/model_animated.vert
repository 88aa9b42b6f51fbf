#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/ModelTypes.h"

// A glTF vertex of an animated model (layers/models/GltfAnimation.h): morphed by its node's
// weights, then placed by its skin's joint matrices or its node's matrix, all read from the
// pose block of its instance; then the instance's model-to-eye transform as in model.vert.
// Static models use model.vert (no pose, no second vertex stream).

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(set = kModelSet, binding = kModelBindingInstances, std430) readonly buffer Instances { ModelInstance instances[]; };
layout(set = kModelSet, binding = kModelBindingPoses, std430) readonly buffer Poses { vec4 poses[]; };
layout(set = kModelSet, binding = kModelBindingMorphDeltas, std430) readonly buffer Morphs { float morphDeltas[]; };
layout(push_constant) uniform PushBlock { ModelPush pc; };

layout(location = kModelInputPosition) in vec3 inPosition;
layout(location = kModelInputNormal) in vec3 inNormal;
layout(location = kModelInputUv) in vec2 inUv;
layout(location = kModelInputColor) in vec4 inColor;
layout(location = kModelInputJoints) in uvec4 inJoints;
layout(location = kModelInputWeights) in vec4 inWeights;

layout(location = 0) out vec3 vNormal;
layout(location = 1) out vec2 vUv;
layout(location = 2) out vec4 vColor;
layout(location = 3) out vec3 vFromEye;

mat4 poseMatrix(uint at) { return mat4(poses[at], poses[at + 1], poses[at + 2], poses[at + 3]); }

float poseFloat(uint at) { return poses[at >> 2][at & 3u]; }

void main() {
    ModelInstance inst = instances[gl_InstanceIndex];
    uint pose = inst.poseBase;
    vec3 position = inPosition;
    vec3 normal = inNormal;
    // Morph targets: (vertex, target) pairs of 6 floats; gl_VertexIndex includes the draw's
    // vertex offset, which pc.morphBase has taken out (modulo 2^32).
    uint targets = pc.morphTargets;
    for (uint k = 0u; k < targets; ++k) {
        float w = poseFloat(pose * 4u + pc.morphWeights + k);
        if (w == 0.0) continue;
        uint d = (pc.morphBase + uint(gl_VertexIndex) * targets + k) * 6u;
        position += w * vec3(morphDeltas[d], morphDeltas[d + 1u], morphDeltas[d + 2u]);
        normal += w * vec3(morphDeltas[d + 3u], morphDeltas[d + 4u], morphDeltas[d + 5u]);
    }
    mat4 m;
    if (pc.joints != kModelPoseNone) {
        uint joints = pose + pc.joints;
        m = inWeights.x * poseMatrix(joints + 4u * inJoints.x) + inWeights.y * poseMatrix(joints + 4u * inJoints.y) +
            inWeights.z * poseMatrix(joints + 4u * inJoints.z) + inWeights.w * poseMatrix(joints + 4u * inJoints.w);
    } else {
        m = poseMatrix(pose + pc.node);
    }
    // The cofactor matrix is the inverse transpose times the determinant: right for normals
    // under any scale (the sign is fixed in the fragment shader, which lights both faces).
    mat3 a = mat3(m);
    mat3 cofactor = mat3(cross(a[1], a[2]), cross(a[2], a[0]), cross(a[0], a[1]));
    vec4 p = inst.modelToEye * (m * vec4(position, 1.0));
    vNormal = mat3(inst.modelToEye) * (cofactor * normal);
    vUv = inUv;
    vColor = inColor * vec4(inst.tint, 1.0);
    vFromEye = p.xyz;
    gl_Position = frame.projection * frame.viewRotation * p;
}
