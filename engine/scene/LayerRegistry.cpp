#include "engine/scene/LayerRegistry.h"

namespace orbis::scene {

void LayerRegistry::add(LayerType type) {
    std::string name = type.name;
    entries_[std::move(name)] = Entry{std::move(type), 0};
}

void LayerRegistry::add(std::string type, std::string description, LayerFactory factory) {
    add(LayerType{std::move(type), std::move(description), std::move(factory), {}});
}

std::vector<std::string> LayerRegistry::types() const {
    std::vector<std::string> out;
    for (const auto& [type, entry] : entries_) out.push_back(type);
    return out;
}

std::string LayerRegistry::description(const std::string& type) const {
    auto it = entries_.find(type);
    return it == entries_.end() ? std::string() : it->second.type.description;
}

const std::vector<std::string>& LayerRegistry::filePaths(const std::string& type) const {
    static const std::vector<std::string> kNone;
    auto it = entries_.find(type);
    return it == entries_.end() ? kNone : it->second.type.filePaths;
}

Result<std::unique_ptr<Layer>> LayerRegistry::create(const LayerDesc& layer, const SceneDesc& scene) const {
    auto it = entries_.find(layer.type);
    if (it == entries_.end()) {
        std::string known;
        for (const auto& t : types()) known += (known.empty() ? "" : ", ") + t;
        return Error{scene.file.string() + ": " + layer.jsonPath + "/type: unknown layer type '" + layer.type +
                     "' (known: " + (known.empty() ? "none" : known) + ")"};
    }
    auto result = it->second.type.factory(layer, scene);
    if (result) ++it->second.constructed;
    return result;
}

int LayerRegistry::constructed(const std::string& type) const {
    auto it = entries_.find(type);
    return it == entries_.end() ? 0 : it->second.constructed;
}

}  // namespace orbis::scene
