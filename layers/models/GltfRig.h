#pragma once
// Reading what glTF poses need (ModelRig in GltfModel.h): the node hierarchy with rest TRS, skins
// and animations. Internal to the glTF reader: GltfModel.cpp calls it after the meshes are read.
// Every inconsistency is an error naming the file and the glTF object ("model.gltf: animation
// 'Walk' channel 2: targets node 17, which does not exist"). No Vulkan.

#include "base/Result.h"
#include "layers/models/GltfModel.h"

#include <functional>
#include <string>

namespace tinygltf {
class Model;
}

namespace orbis::models {

class GltfAccessors;

/// Fills out.rig's nodes, order, skins and animations. `meshTargets[m]`: the morph targets of
/// mesh m's primitives (checked equal across a mesh by the caller). `warn` takes what is left out.
Result<void> readRig(const tinygltf::Model& model, const GltfAccessors& accessors, const std::string& file,
                     const std::vector<uint32_t>& meshTargets, ModelData& out,
                     const std::function<void(const std::string&)>& warn);

}  // namespace orbis::models
