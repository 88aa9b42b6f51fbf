#pragma once
// What a layer learns about the frame it is updated for: the camera, the scene's time, the size,
// the ground. The passes of a frame, in order. No Vulkan: recording needs engine/render's
// RecordContext.

#include "base/TimeFormat.h"
#include "engine/scene/Annotation.h"
#include "engine/scene/Camera.h"
#include "globe/TileImageSource.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace orbis::scene {

/// The passes of a frame, in order (docs/ARCHITECTURE.md, "A frame").
enum class Pass { Opaque, Points, Fmv, Volume, Overlay };

/// Height of the ground above the ellipsoid at (lon, lat), or nothing where unknown.
using GroundHeightFn = std::function<std::optional<double>(double lonDeg, double latDeg)>;

/// One visible layer's content draped on the ground this frame (DrapedContent).
class DrapedContent;

struct Drape {
    const void* owner = nullptr;   ///< the layer: the same one from frame to frame
    std::shared_ptr<const globe::TileImageSource> source;
    uint64_t version = 0;
    double opacity = 1.0;
    const DrapedContent* content = nullptr;   ///< the owner's capability (where a change is)
};

struct FrameContext {
    const Camera* camera = nullptr;
    TimeNs time = 0;
    uint32_t width = 0, height = 0;
    uint64_t frameNumber = 0;
    double cameraHeight = 0.0;   ///< above the ellipsoid, metres
    /// The ground's height above the ellipsoid where a visible layer knows it (the terrain's
    /// loaded data), else nothing: Scene::heightAt.
    GroundHeightFn groundHeight;
    /// Changes whenever groundHeight's answers may have (GroundSource::groundVersion, summed).
    uint64_t groundVersion = 0;
    /// groundHeight's answers as a function any thread may call (Scene::groundSnapshot), made
    /// when asked: for layers that sample the ground on the worker pool.
    std::function<GroundHeightFn()> groundSnapshot;
    /// The scene's pins (Scene::annotations), for the layer that draws them.
    const std::vector<Annotation>* annotations = nullptr;
    /// What visible layers drape on the ground, in scene order, for the ground layer.
    std::vector<Drape> drapes;
    double aspect() const { return height ? double(width) / double(height) : 1.0; }
};

}  // namespace orbis::scene
