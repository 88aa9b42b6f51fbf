// 3-D models (layers/models/ModelLayer.h). Set kModelSet (per frame in flight): the instances
// drawn this frame (ModelInstance[], picked by gl_InstanceIndex) and the model's node
// transforms (ModelNode[], picked by the push constant; static models). Animated models
// (model_animated.vert) have instead the poses drawn this frame (vec4[], blocks laid out by
// layers/models/GltfAnimation.h's PoseLayout, an instance's block at ModelInstance::poseBase)
// and the morph target deltas (float[], 6 per vertex and target), plus a second vertex stream
// with joints and weights. Set kModelMaterialSet: the material's base colour texture
// (sampler2D, sRGB). Paths and labels are polylines (shared/PolylineTypes.h,
// shaders/common/polyline.*).
//
// Positions on the GPU are relative to the eye: each instance's model-to-eye transform is
// built in double on the CPU (ECEF origin minus eye), then sent as float.
#ifndef ORBIS_SHADERS_SHARED_MODEL_TYPES_H
#define ORBIS_SHADERS_SHARED_MODEL_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kModelSet, 1)
ORBIS_CONST(uint, kModelBindingInstances, 0)
ORBIS_CONST(uint, kModelBindingNodes, 1)        // static models
ORBIS_CONST(uint, kModelBindingPoses, 2)        // animated models
ORBIS_CONST(uint, kModelBindingMorphDeltas, 3)  // animated models
ORBIS_CONST(uint, kModelMaterialSet, 2)
ORBIS_CONST(uint, kModelBindingBaseColor, 0)

// Vertex inputs: models::ModelVertex (stream 0), then models::ModelSkinVertex (stream 1,
// animated models).
ORBIS_CONST(uint, kModelInputPosition, 0)
ORBIS_CONST(uint, kModelInputNormal, 1)
ORBIS_CONST(uint, kModelInputUv, 2)
ORBIS_CONST(uint, kModelInputColor, 3)
ORBIS_CONST(uint, kModelInputJoints, 4)
ORBIS_CONST(uint, kModelInputWeights, 5)

ORBIS_CONST(uint, kModelPoseNone, 0xffffffffu)   // a pose part a draw does not have

// std430.
struct ModelInstance {
    mat4 modelToEye;   // model space (glTF axes) -> world axes relative to the eye: rotation x scale, translation
    vec3 tint;         // multiplies the material colour (linear)
    float pad0;
    uint poseBase;     // the first vec4 of its pose block (animated models)
    uint pad1;
    uint pad2;
    uint pad3;
};

struct ModelNode {
    mat4 transform;    // node -> model space
    mat4 normal;       // inverse transpose of the upper 3x3 (columns in xyz)
};

// Push constants, per drawn primitive.
struct ModelPush {
    vec4 baseColor;      // the material's factor (linear RGBA)
    float alphaCutoff;   // MASK materials; -1: none
    uint unlit;          // 1: KHR_materials_unlit
    uint sunLighting;    // 1: the sun, 0: a headlight
    uint textured;       // 1: the material has a base colour texture
    uint node;           // static: the node's index. Animated: its matrix in the pose block (vec4s)
    uint joints;         // animated: the skin's joint matrices in the pose block (vec4s), or kModelPoseNone
    uint morphTargets;   // animated: the primitive's morph targets (0: none)
    uint morphWeights;   // animated: the node's morph weights in the pose block (floats)
    uint morphBase;      // (first delta pair of the primitive) - (vertex offset) x targets, modulo 2^32
    uint pad0;
    uint pad1;
    uint pad2;
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
namespace orbis::shader {
/// Set kModelSet of a static model, one per frame in flight (layers/models/ModelLayer.cpp).
inline constexpr DescriptorBinding kModelStaticBindings[] = {
    {kModelBindingInstances, DescriptorKind::StorageBuffer, 1, kStageVertex},
    {kModelBindingNodes, DescriptorKind::StorageBuffer, 1, kStageVertex},
};
/// Set kModelSet of an animated model.
inline constexpr DescriptorBinding kModelAnimatedBindings[] = {
    {kModelBindingInstances, DescriptorKind::StorageBuffer, 1, kStageVertex},
    {kModelBindingPoses, DescriptorKind::StorageBuffer, 1, kStageVertex},
    {kModelBindingMorphDeltas, DescriptorKind::StorageBuffer, 1, kStageVertex},
};
/// Set kModelMaterialSet, one per texture.
inline constexpr DescriptorBinding kModelMaterialBindings[] = {
    {kModelBindingBaseColor, DescriptorKind::CombinedImageSampler, 1, kStageFragment},
};
}  // namespace orbis::shader
static_assert(sizeof(orbis::shader::ModelInstance) == 96, "ModelInstance layout changed");
static_assert(offsetof(orbis::shader::ModelInstance, poseBase) == 80, "std430 offset");
static_assert(sizeof(orbis::shader::ModelNode) == 128, "ModelNode layout changed");
static_assert(sizeof(orbis::shader::ModelPush) == 64, "ModelPush must fit push constants");
static_assert(offsetof(orbis::shader::ModelPush, node) == 32 && offsetof(orbis::shader::ModelPush, morphBase) == 48,
              "std430 offset");
#endif

#endif
