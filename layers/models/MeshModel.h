#pragma once
// Models in the mesh formats users bring, read through the Open Asset Import Library (Debian's
// libassimp): Wavefront OBJ + MTL, FBX, COLLADA (.dae, and the model a KMZ holds), 3DS, PLY and
// STL, into the same flat, GPU-ready ModelData the glTF reader makes (GltfModel.h): every
// triangle mesh of the node hierarchy a range of one shared vertex/index array, drawn with its
// node's transform. A file's node animations (translation, rotation and scale keys of its nodes:
// FBX, COLLADA, ...) become a rig with glTF's animation model (GltfAnimation.h) and play as
// glTF's do, when they move a node that draws; skins, mesh and morph animations are not read
// (their meshes keep the rest pose, with a warning). glTF keeps its own reader. No Vulkan.
//
// Axes and units. ModelData is in glTF's axes (metres, +Y up, the front facing +Z). What a file
// says is honoured: FBX's axis and unit settings (UpAxis, FrontAxis, CoordAxis with their signs;
// UnitScaleFactor, centimetres per unit), COLLADA's <up_axis> and <unit> (applied by Assimp).
// Formats that say nothing are taken as +Y up in metres, but 3DS, +Z up as 3ds Max writes it;
// `MeshImportOptions` overrides both (a Z-up CAD export in millimetres: up 'z', unit 0.001).
//
// Materials: the diffuse (or base) colour and opacity (below 1: blended), the first diffuse or
// base-colour texture with its wrap modes (repeat, clamp, mirror; "decal" as clamp),
// two-sidedness, unlit shading; vertex colours (the first set). Texture
// paths as files write them, Windows ones included: backslashes, absolute paths from the
// author's disk, different case; looked for beside the model, then by their file name alone,
// then with any case. Embedded textures (FBX, "*N") are read from the file. A texture that
// cannot be found or decoded is drawn white with a warning. Points and lines are left out with a
// warning.
//
// Bounds on input: files over kMaxGltfFileBytes, models over kMaxGltfVertices or kMaxGltfIndices,
// images over kMaxGltfImageSide a side are refused; a node hierarchy deeper than 256 is an error.
// Assimp's validation runs on every file (indices inside their meshes, counts consistent).
// Messages name the file.

#include "base/Result.h"
#include "layers/models/GltfModel.h"

#include <optional>
#include <string>

namespace orbis::models {

struct MeshImportOptions {
    std::optional<char> up;              ///< 'y' or 'z': the file's up axis, over what it says or its format's custom
    std::optional<double> unitMetres;    ///< metres per file unit, over what the file says
};

/// True for the extensions loadMesh reads (.obj, .fbx, .dae, .kmz, .3ds, .ply, .stl; any case).
bool isMeshFormat(const std::string& path);

/// Reads `path`: a mesh file, or a KMZ (the COLLADA model its KML's first <Model> links, read
/// from inside the archive with its textures).
Result<ModelData> loadMesh(const std::string& path, const MeshImportOptions& options = {});

}  // namespace orbis::models
