#include "engine/scene/LayerRegistry.h"

namespace orbis::scene {

void LayerRegistry::add(std::string type, std::string description, LayerFactory factory) {
    entries_[std::move(type)] = Entry{std::move(description), std::move(factory), 0};
}

std::vector<std::string> LayerRegistry::types() const {
    std::vector<std::string> out;
    for (const auto& [type, entry] : entries_) out.push_back(type);
    return out;
}

std::string LayerRegistry::description(const std::string& type) const {
    auto it = entries_.find(type);
    return it == entries_.end() ? std::string() : it->second.description;
}

Result<std::unique_ptr<Layer>> LayerRegistry::create(const LayerDesc& layer, const SceneDesc& scene) const {
    auto it = entries_.find(layer.type);
    if (it == entries_.end()) {
        std::string known;
        for (const auto& t : types()) known += (known.empty() ? "" : ", ") + t;
        return Error{scene.file.string() + ": " + layer.jsonPath + "/type: unknown layer type '" + layer.type +
                     "' (known: " + (known.empty() ? "none" : known) + ")"};
    }
    auto result = it->second.factory(layer, scene);
    if (result) ++it->second.constructed;
    return result;
}

int LayerRegistry::constructed(const std::string& type) const {
    auto it = entries_.find(type);
    return it == entries_.end() ? 0 : it->second.constructed;
}

}  // namespace orbis::scene
