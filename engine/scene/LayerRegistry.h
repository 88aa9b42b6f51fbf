#pragma once
// Maps a scene's "type" strings to layer factories. Apps register the built-in types at start
// (tools/orbis/Layers.cpp); nothing registers itself through static initialisers. It counts what
// it constructs, so tests can prove an unused type was never built.

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

class LayerRegistry {
public:
    void add(std::string type, std::string description, LayerFactory factory);
    bool has(const std::string& type) const { return entries_.count(type) != 0; }
    std::vector<std::string> types() const;
    std::string description(const std::string& type) const;

    /// Constructs the layer; an unknown type is an error naming the known ones.
    Result<std::unique_ptr<Layer>> create(const LayerDesc& layer, const SceneDesc& scene) const;
    /// How many layers of `type` this registry has constructed.
    int constructed(const std::string& type) const;

private:
    struct Entry {
        std::string description;
        LayerFactory factory;
        mutable int constructed = 0;
    };
    std::map<std::string, Entry> entries_;
};

}  // namespace orbis::scene
