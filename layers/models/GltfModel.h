#pragma once
// glTF 2.0 models (.gltf with embedded or external buffers and images, and .glb) read through
// tinygltf into one flat, GPU-ready form: every triangle primitive of the default scene's node
// hierarchy becomes a range of one shared vertex/index array, drawn with its node's transform.
// No Vulkan.
//
// Conventions. glTF is right-handed, metres, +Y up, the front of an asset faces +Z, so +X is
// the asset's left. Model data stays in glTF axes here; `gltfToBody()` gives the fixed rotation
// onto the vehicle body axes of a trajectory pose (x forward, y right, z down):
//   body x (forward) =  glTF +Z,   body y (right) = glTF -X,   body z (down) = glTF -Y.
// It is motion::gltfToBody() (formats/motion/Attitude.h), where the convention is written once.
//
// What is read: positions, normals (flat normals are made when a primitive has none), the first
// texture coordinates, COLOR_0, indices (8, 16, 32 bit or none), TRIANGLES / TRIANGLE_STRIP /
// TRIANGLE_FAN (strips and fans become lists), node matrices or TRS, materials' base colour
// factor and texture, alpha mode (OPAQUE, MASK with its cutoff, BLEND), double-sidedness, and
// KHR_materials_unlit; for animation (GltfAnimation.h) the node hierarchy with its rest TRS, skins
// (JOINTS_0 / WEIGHTS_0, inverse bind matrices), morph targets (POSITION and NORMAL deltas, sparse
// accessors included; TANGENT is not used) and animations (translation, rotation, scale and
// weights channels; STEP, LINEAR, CUBICSPLINE). Points and lines are left out with a warning; a
// required extension that is not understood (Draco, meshopt, ...) is an error, since the
// geometry could not be read.
//
// Two forms. A model with no skin, no morph target and no animation is only the flat draw list
// (each draw's node transform baked in `ModelDraw::transform`): the fast path. Otherwise
// `ModelData::rig` also holds what a pose needs, and `animated()` is true.
//
// Bounds on input: files over kMaxGltfFileBytes are refused before reading; every accessor is
// checked against its buffer view and buffer; a model over kMaxGltfVertices or kMaxGltfIndices
// (after flattening) and images over kMaxGltfImageSide are refused. Messages name the file and
// the glTF object ("model.gltf: accessor 3 (POSITION of mesh 'Wheel'): runs past its buffer").

#include "base/Result.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace orbis::models {

inline constexpr uint64_t kMaxGltfFileBytes = uint64_t(512) << 20;
inline constexpr uint64_t kMaxGltfVertices = uint64_t(32) << 20;
inline constexpr uint64_t kMaxGltfIndices = uint64_t(96) << 20;
inline constexpr uint32_t kMaxGltfImageSide = 8192;
inline constexpr uint32_t kMaxGltfJoints = 1024;          ///< per skin
inline constexpr uint32_t kMaxGltfMorphTargets = 64;      ///< per mesh
inline constexpr uint64_t kMaxGltfMorphDeltas = uint64_t(8) << 20;   ///< (vertex, target) pairs in all
inline constexpr uint64_t kMaxGltfKeyframes = uint64_t(4) << 20;     ///< in all samplers of all animations

/// 36 bytes, tightly packed: what the model vertex shader reads.
struct ModelVertex {
    float position[3];
    float normal[3];
    float uv[2];
    uint32_t color;   ///< RGBA8 (linear), from COLOR_0, else white
};
static_assert(sizeof(ModelVertex) == 36);

/// What a texture coordinate outside 0..1 samples (glTF's sampler wrap modes; Assimp's mapping
/// modes, its "decal" as clamp).
enum class TextureWrap : uint8_t { Repeat, Clamp, Mirror };

/// An RGBA8 image with its mip chain (box-filtered on the CPU), level 0 first.
struct ModelTexture {
    std::string name;
    uint32_t width = 0, height = 0;
    std::vector<std::vector<uint8_t>> mips;   ///< mips[i]: max(1, w >> i) x max(1, h >> i) x 4 bytes
    TextureWrap wrapU = TextureWrap::Repeat, wrapV = TextureWrap::Repeat;   ///< outside 0..1
    bool nearest = false;                     ///< the sampler asks for nearest magnification
};

enum class AlphaMode { Opaque, Mask, Blend };

struct ModelMaterial {
    std::string name;
    glm::vec4 baseColorFactor{1.0f};   ///< linear RGBA
    int baseColorTexture = -1;         ///< index into ModelData::textures, or -1
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;
    bool doubleSided = false;
    bool unlit = false;                ///< KHR_materials_unlit
};

/// A range of the shared index array, with one material.
struct ModelPrimitive {
    uint32_t firstIndex = 0, indexCount = 0;
    int32_t vertexOffset = 0;
    uint32_t vertexCount = 0;
    int material = -1;                 ///< -1: the default material (white, opaque)
    uint32_t morphTargets = 0;         ///< morph targets of its mesh (0: none)
    uint32_t morphBase = 0;            ///< first (vertex, target) pair of its deltas in ModelRig::morphDeltas
    bool skinned = false;              ///< has JOINTS_0 and WEIGHTS_0 (ModelRig::skinVertices)
    uint32_t maxJoint = 0;             ///< the largest joint index its vertices name (skinned)
};

/// One primitive drawn with one node's transform (a mesh used by several nodes gives several).
struct ModelDraw {
    uint32_t primitive = 0;
    glm::mat4 transform{1.0f};         ///< node to model space (glTF axes), parents applied (rest pose)
    bool mirrored = false;             ///< the transform flips handedness (det < 0): front faces swap
    int node = -1;                     ///< the glTF node that draws it
    int skin = -1;                     ///< the node's skin when the primitive is skinned, else -1
};

// ---- What poses need (only for models that animate, skin or morph; GltfAnimation.h) ----

enum class AnimationPath { Translation, Rotation, Scale, Weights };
enum class AnimationInterpolation { Step, Linear, CubicSpline };

/// One glTF animation sampler: keyframe times (seconds, strictly increasing) and their values.
struct AnimationSampler {
    std::vector<float> times;
    /// Per keyframe `components` numbers (STEP, LINEAR) or three groups of them (CUBICSPLINE:
    /// in-tangent, value, out-tangent), keyframe after keyframe as in the file.
    std::vector<float> values;
    uint32_t components = 0;           ///< 3 translation and scale, 4 rotation (x, y, z, w), morph targets for weights
    AnimationInterpolation interpolation = AnimationInterpolation::Linear;
};

struct AnimationChannel {
    uint32_t node = 0;
    AnimationPath path = AnimationPath::Translation;
    uint32_t sampler = 0;
};

struct ModelAnimation {
    std::string name;
    std::vector<AnimationSampler> samplers;
    std::vector<AnimationChannel> channels;
    double duration = 0.0;             ///< the last keyframe time of all its samplers (seconds)
};

/// A glTF node as animation sees it: its rest transform and its place in the hierarchy.
struct RigNode {
    std::string name;
    int parent = -1;
    glm::dvec3 translation{0.0};
    glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
    glm::dvec3 scale{1.0};
    bool hasMatrix = false;            ///< given as a matrix: not animatable (glTF 2.0, 5.25)
    glm::dmat4 matrix{1.0};            ///< the matrix when hasMatrix
    std::vector<float> weights;        ///< rest morph weights (the node's, else its mesh's); empty without targets
};

struct ModelSkin {
    std::string name;
    std::vector<uint32_t> joints;      ///< node indices
    std::vector<glm::mat4> inverseBind;   ///< one per joint (identity when the file gives none)
};

/// Joints and weights of a skinned vertex, beside ModelVertex (second vertex stream).
struct ModelSkinVertex {
    uint16_t joints[4];
    float weights[4];
};
static_assert(sizeof(ModelSkinVertex) == 24);

struct ModelRig {
    std::vector<RigNode> nodes;        ///< every glTF node, in file order
    std::vector<uint32_t> order;       ///< every node, parents before their children
    std::vector<ModelSkin> skins;
    std::vector<ModelAnimation> animations;
    std::vector<ModelSkinVertex> skinVertices;   ///< parallel to ModelData::vertices when a primitive is skinned
    std::vector<float> morphDeltas;    ///< 6 floats per (vertex, target): position delta, normal delta
};

struct ModelData {
    std::string file;
    std::vector<ModelVertex> vertices;
    std::vector<uint32_t> indices;
    std::vector<ModelPrimitive> primitives;
    std::vector<ModelDraw> draws;
    std::vector<ModelMaterial> materials;
    std::vector<ModelTexture> textures;
    glm::dvec3 boundsMin{0.0}, boundsMax{0.0};   ///< model space (glTF axes) of every draw
    uint64_t triangles = 0;                       ///< drawn triangles, all draws
    std::vector<std::string> warnings;            ///< what was left out, one line each
    ModelRig rig;                                 ///< empty unless animated()
    /// Skins, morph targets or animations: drawn through poses (GltfAnimation.h), not the fast path.
    bool animated() const { return !rig.nodes.empty(); }
    double radius() const { return 0.5 * glm::length(boundsMax - boundsMin); }
    glm::dvec3 center() const { return 0.5 * (boundsMin + boundsMax); }
    uint64_t textureBytes() const;
};

/// Reads `path` (.glb, or .gltf with its buffers and images beside it or embedded).
Result<ModelData> loadGltf(const std::string& path);

/// glTF model axes -> body axes (x forward, y right, z down): motion::gltfToBody().
glm::dmat3 gltfToBody();

/// The mip chain of an RGBA8 image (2x2 box filter, odd sizes clamp), level 0 included.
std::vector<std::vector<uint8_t>> buildMips(const uint8_t* rgba, uint32_t width, uint32_t height);

}  // namespace orbis::models
