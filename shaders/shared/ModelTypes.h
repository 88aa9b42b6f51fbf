// 3-D models (layers/models/ModelLayer.h). Set 1 (per frame in flight): binding 0 the instances
// drawn this frame (ModelInstance[], picked by gl_InstanceIndex), binding 1 the model's node
// transforms (ModelNode[], picked by the push constant). Set 2: the material's base colour
// texture (sampler2D, sRGB). Paths and labels use set 0 only and their own vertex streams.
//
// Positions on the GPU are relative to the eye: each instance's model-to-eye transform is
// built in double on the CPU (ECEF origin minus eye), then sent as float.
#ifndef ORBIS_SHADERS_SHARED_MODEL_TYPES_H
#define ORBIS_SHADERS_SHARED_MODEL_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kModelSet, 1)
ORBIS_CONST(uint, kModelMaterialSet, 2)

// std430; 16-byte members only.
struct ModelInstance {
    mat4 modelToEye;   // model space (glTF axes) -> world axes relative to the eye: rotation x scale, translation
    vec4 tint;         // rgb: multiplies the material colour (linear); a: unused
};

struct ModelNode {
    mat4 transform;    // node -> model space
    mat4 normal;       // inverse transpose of the upper 3x3 (columns in xyz)
};

// Push constants, per drawn primitive.
struct ModelPush {
    vec4 baseColor;    // the material's factor (linear RGBA)
    vec4 params;       // x: alpha cutoff (MASK) or -1; y: 1 = unlit; z: 1 = sun lighting, 0 = headlight; w: 1 = textured
    uvec4 ids;         // x: node index
};

// The path line and the label quads: one vertex each.
struct ModelLineVertex {
    vec4 position;     // xyz: relative to the eye (metres, world axes); w: 1
    vec4 color;        // linear RGBA
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(orbis::shader::ModelInstance) == 80, "ModelInstance layout changed");
static_assert(sizeof(orbis::shader::ModelNode) == 128, "ModelNode layout changed");
static_assert(sizeof(orbis::shader::ModelPush) == 48, "ModelPush must fit push constants");
static_assert(sizeof(orbis::shader::ModelLineVertex) == 32, "ModelLineVertex layout changed");
#endif

#endif
