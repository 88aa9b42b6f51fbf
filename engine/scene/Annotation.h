#pragma once
// A labelled pin on the globe: placed by the user in the viewer or listed in the scene file
// ("annotations"), drawn by the annotation layer, saved with the scene. No Vulkan.

#include <string>

namespace orbis::scene {

/// The layer type that draws the pins (Scene::ensureAnnotationLayer).
inline constexpr const char* kAnnotationLayerType = "annotations";

struct Annotation {
    std::string name;
    double lonDeg = 0.0;
    double latDeg = 0.0;
    double height = 0.0;   ///< above the ellipsoid, metres
};

}  // namespace orbis::scene
