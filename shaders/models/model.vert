#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/ModelTypes.h"

// A glTF vertex through its node's transform and its instance's model-to-eye transform (both
// small numbers: the instance's ECEF origin minus the eye was taken in double on the CPU).

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(set = kModelSet, binding = kModelBindingInstances, std430) readonly buffer Instances { ModelInstance instances[]; };
layout(set = kModelSet, binding = kModelBindingNodes, std430) readonly buffer Nodes { ModelNode nodes[]; };
layout(push_constant) uniform PushBlock { ModelPush pc; };

layout(location = kModelInputPosition) in vec3 inPosition;
layout(location = kModelInputNormal) in vec3 inNormal;
layout(location = kModelInputUv) in vec2 inUv;
layout(location = kModelInputColor) in vec4 inColor;

layout(location = 0) out vec3 vNormal;
layout(location = 1) out vec2 vUv;
layout(location = 2) out vec4 vColor;
layout(location = 3) out vec3 vFromEye;

void main() {
    ModelInstance inst = instances[gl_InstanceIndex];
    ModelNode node = nodes[pc.node];
    vec4 p = inst.modelToEye * (node.transform * vec4(inPosition, 1.0));
    vNormal = mat3(inst.modelToEye) * (mat3(node.normal) * inNormal);
    vUv = inUv;
    vColor = inColor * vec4(inst.tint, 1.0);
    vFromEye = p.xyz;
    gl_Position = frame.projection * frame.viewRotation * p;
}
