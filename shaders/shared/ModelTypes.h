// 3-D models (layers/models/ModelLayer.h). Set 1 (per frame in flight): binding 0 the instances
// drawn this frame (ModelInstance[], picked by gl_InstanceIndex), binding 1 the model's node
// transforms (ModelNode[], picked by the push constant; static models). Animated models
// (model_animated.vert) have instead binding 2, the poses drawn this frame (vec4[], blocks laid
// out by layers/models/GltfAnimation.h's PoseLayout, an instance's block at ModelInstance::pose.x),
// and binding 3 the morph target deltas (float[], 6 per vertex and target), plus a second vertex
// stream with joints and weights. Set 2: the material's base colour texture (sampler2D, sRGB).
// Paths and labels are polylines (shared/PolylineTypes.h, shaders/common/polyline.*).
//
// Positions on the GPU are relative to the eye: each instance's model-to-eye transform is
// built in double on the CPU (ECEF origin minus eye), then sent as float.
#ifndef ORBIS_SHADERS_SHARED_MODEL_TYPES_H
#define ORBIS_SHADERS_SHARED_MODEL_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kModelSet, 1)
ORBIS_CONST(uint, kModelMaterialSet, 2)
ORBIS_CONST(uint, kModelPoseNone, 0xffffffffu)   // a pose part a draw does not have

// std430; 16-byte members only.
struct ModelInstance {
    mat4 modelToEye;   // model space (glTF axes) -> world axes relative to the eye: rotation x scale, translation
    vec4 tint;         // rgb: multiplies the material colour (linear); a: unused
    uvec4 pose;        // x: the first vec4 of its pose block (animated models); yzw: unused
};

struct ModelNode {
    mat4 transform;    // node -> model space
    mat4 normal;       // inverse transpose of the upper 3x3 (columns in xyz)
};

// Push constants, per drawn primitive.
struct ModelPush {
    vec4 baseColor;    // the material's factor (linear RGBA)
    vec4 params;       // x: alpha cutoff (MASK) or -1; y: 1 = unlit; z: 1 = sun lighting, 0 = headlight; w: 1 = textured
    uvec4 ids;         // static: x the node index. Animated, offsets in the pose block: x the node
                       // matrix (vec4s), y the skin's joint matrices (vec4s) or kModelPoseNone,
                       // z the morph targets, w the node's morph weights (floats)
    uvec4 morph;       // x: (first delta pair of the primitive) - (vertex offset) x targets, modulo 2^32
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(orbis::shader::ModelInstance) == 96, "ModelInstance layout changed");
static_assert(sizeof(orbis::shader::ModelNode) == 128, "ModelNode layout changed");
static_assert(sizeof(orbis::shader::ModelPush) == 64, "ModelPush must fit push constants");
#endif

#endif
