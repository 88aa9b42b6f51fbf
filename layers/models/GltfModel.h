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
//
// What is read: positions, normals (flat normals are made when a primitive has none), the first
// texture coordinates, COLOR_0, indices (8, 16, 32 bit or none), TRIANGLES / TRIANGLE_STRIP /
// TRIANGLE_FAN (strips and fans become lists), node matrices or TRS, materials' base colour
// factor and texture, alpha mode (OPAQUE, MASK with its cutoff, BLEND), double-sidedness, and
// KHR_materials_unlit. Points and lines, morph targets, skins and glTF animations are left out
// with a warning (the model is drawn in its rest pose); a required extension that is not
// understood (Draco, meshopt, ...) is an error, since the geometry could not be read.
//
// Bounds on input: files over kMaxGltfFileBytes are refused before reading; every accessor is
// checked against its buffer view and buffer; a model over kMaxGltfVertices or kMaxGltfIndices
// (after flattening) and images over kMaxGltfImageSide are refused. Messages name the file and
// the glTF object ("model.gltf: accessor 3 (POSITION of mesh 'Wheel'): runs past its buffer").

#include "engine/core/Result.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace orbis::models {

inline constexpr uint64_t kMaxGltfFileBytes = uint64_t(512) << 20;
inline constexpr uint64_t kMaxGltfVertices = uint64_t(32) << 20;
inline constexpr uint64_t kMaxGltfIndices = uint64_t(96) << 20;
inline constexpr uint32_t kMaxGltfImageSide = 8192;

/// 36 bytes, tightly packed: what the model vertex shader reads.
struct ModelVertex {
    float position[3];
    float normal[3];
    float uv[2];
    uint32_t color;   ///< RGBA8 (linear), from COLOR_0, else white
};
static_assert(sizeof(ModelVertex) == 36);

/// An RGBA8 image with its mip chain (box-filtered on the CPU), level 0 first.
struct ModelTexture {
    std::string name;
    uint32_t width = 0, height = 0;
    std::vector<std::vector<uint8_t>> mips;   ///< mips[i]: max(1, w >> i) x max(1, h >> i) x 4 bytes
    bool repeatU = true, repeatV = true;      ///< the sampler's wrap modes (mirrored counts as repeat)
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
    int material = -1;                 ///< -1: the default material (white, opaque)
};

/// One primitive drawn with one node's transform (a mesh used by several nodes gives several).
struct ModelDraw {
    uint32_t primitive = 0;
    glm::mat4 transform{1.0f};         ///< node to model space (glTF axes), parents applied
    bool mirrored = false;             ///< the transform flips handedness (det < 0): front faces swap
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
    double radius() const { return 0.5 * glm::length(boundsMax - boundsMin); }
    glm::dvec3 center() const { return 0.5 * (boundsMin + boundsMax); }
    uint64_t textureBytes() const;
};

/// Reads `path` (.glb, or .gltf with its buffers and images beside it or embedded).
Result<ModelData> loadGltf(const std::string& path);

/// glTF model axes -> body axes (x forward, y right, z down): see the header comment.
glm::dmat3 gltfToBody();

/// The mip chain of an RGBA8 image (2x2 box filter, odd sizes clamp), level 0 included.
std::vector<std::vector<uint8_t>> buildMips(const uint8_t* rgba, uint32_t width, uint32_t height);

}  // namespace orbis::models
