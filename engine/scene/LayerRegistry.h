#pragma once
// Maps a scene's "type" strings to layer types: a factory, a description, and where the files
// of a layer's scene object are. Apps register the built-in types at start
// (layers/BuiltinLayers.cpp: each layer's folder describes its type, e.g.
// VolumeLayer::layerType()); nothing registers itself through static initialisers. It counts
// what it constructs, so tests can prove an unused type was never built.

#include "base/Result.h"
#include "engine/scene/Layer.h"
#include "engine/scene/SceneDesc.h"

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace orbis::scene {

using LayerFactory = std::function<Result<std::unique_ptr<Layer>>(const LayerDesc&, const SceneDesc&)>;

/// One kind of layer as scene files name it.
struct LayerType {
    std::string name;          ///< the scene's "type"
    std::string description;   ///< for `orbis info` and errors
    LayerFactory factory;
    /// The file paths in the layer's scene object, as JSON pointers in which "*" stands for
    /// any element of an array ("/path", "/imagery/*", "/imagery/*/path"): saving the scene into
    /// another folder rewrites them (SceneSave.h, rebaseLayerPaths).
    std::vector<std::string> filePaths;
};

class LayerRegistry {
public:
    void add(LayerType type);
    /// A type without files.
    void add(std::string type, std::string description, LayerFactory factory);
    bool has(const std::string& type) const { return entries_.count(type) != 0; }
    std::vector<std::string> types() const;
    std::string description(const std::string& type) const;
    /// LayerType::filePaths of `type`; empty for unknown types.
    const std::vector<std::string>& filePaths(const std::string& type) const;

    /// Constructs the layer; an unknown type is an error naming the known ones.
    Result<std::unique_ptr<Layer>> create(const LayerDesc& layer, const SceneDesc& scene) const;
    /// How many layers of `type` this registry has constructed.
    int constructed(const std::string& type) const;

private:
    struct Entry {
        LayerType type;
        mutable int constructed = 0;
    };
    std::map<std::string, Entry> entries_;
};

}  // namespace orbis::scene
