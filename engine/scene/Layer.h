#pragma once
// The interface every kind of content implements (globe, terrain, volume, points, FMV, models).
// A layer is constructed only when the scene names its type, and its GPU objects (pipelines,
// buffers, textures, threads) are made only in prepare(), called before the first frame in
// which the layer is visible: what a scene does not show is never built.

#include "base/TimeFormat.h"
#include "engine/scene/Annotation.h"
#include "engine/scene/Camera.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::gpu {
class Device;
class Uploader;
class Image;
}  // namespace orbis::gpu
namespace orbis::jobs {
class ThreadPool;
}

namespace orbis::scene {

/// The passes of a frame, in order (see DESIGN.md, "A frame").
enum class Pass { Opaque, Points, Fmv, Volume, Overlay };

/// What the renderer lends to layers for building GPU objects. Main thread only.
struct RenderServices {
    gpu::Device* device = nullptr;
    gpu::Uploader* uploader = nullptr;
    VkFormat colorFormat = VK_FORMAT_UNDEFINED;
    VkFormat depthFormat = VK_FORMAT_UNDEFINED;
    VkDescriptorSetLayout frameSetLayout = VK_NULL_HANDLE;   ///< set 0: FrameUniforms
    uint32_t framesInFlight = 2;                              ///< RecordContext::slot < this
    /// The shared worker pool, started on first call (a scene that needs no threads starts none).
    std::function<jobs::ThreadPool&()> jobs;
};

/// Height of the ground above the ellipsoid at (lon, lat), or nothing where unknown.
using GroundHeightFn = std::function<std::optional<double>(double lonDeg, double latDeg)>;

struct FrameContext {
    const Camera* camera = nullptr;
    TimeNs time = 0;
    uint32_t width = 0, height = 0;
    uint64_t frameNumber = 0;
    double cameraHeight = 0.0;   ///< above the ellipsoid, metres
    /// The ground's height above the ellipsoid where a visible layer knows it (the terrain's
    /// loaded data), else nothing: Scene::heightAt.
    GroundHeightFn groundHeight;
    /// Changes whenever groundHeight's answers may have (Layer::groundVersion, summed).
    uint64_t groundVersion = 0;
    /// The scene's pins (Scene::annotations), for the layer that draws them.
    const std::vector<Annotation>* annotations = nullptr;
    double aspect() const { return height ? double(width) / double(height) : 1.0; }
};

/// Where a moving thing is (a vehicle along its trajectory, a live position), for cameras that
/// follow it and for the scene's time range.
struct TrackedPose {
    glm::dvec3 position{0.0};              ///< ECEF metres
    glm::dquat bodyToEcef{1.0, 0.0, 0.0, 0.0};   ///< body axes (x forward, y right, z down) in ECEF
    glm::dvec3 velocity{0.0};              ///< ECEF metres per second
    double radius = 1.0;                   ///< bounding radius of what is drawn there, metres
};

struct TimeRange {
    TimeNs start = 0, end = 0;
};

/// A sphere around everything a layer may draw over time (a whole path), for overview cameras.
struct ContentBounds {
    glm::dvec3 center{0.0};   ///< ECEF
    double radius = 0.0;
};

struct RecordContext {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    const FrameContext* frame = nullptr;
    VkDescriptorSet frameSet = VK_NULL_HANDLE;
    gpu::Uploader* uploader = nullptr;
    uint32_t slot = 0;   ///< frame-in-flight index: per-frame buffers written by the CPU use it
    /// recordCompute only: the scene depth so far (reversed-Z, D32), in ImageUse::SampledCompute.
    gpu::Image* sceneDepth = nullptr;
};

/// One live setting of a layer, as the viewer's panels show it and as a saved scene writes it.
/// `name` is the key setParameter/setOption take and the key of the layer's object in the scene
/// file (so that saving writes `name: value` and loading reads it back).
struct LayerSetting {
    enum class Kind {
        Number,    ///< setParameter(name, value), value in [min, max]
        Integer,   ///< the same, whole numbers
        Toggle,    ///< setParameter(name, 0 or 1); written to the scene as true/false
        Choice,    ///< setOption(name, one of choices)
        Curve,     ///< setCurve(name, points): piecewise linear, x over [min, max], y in 0..1
    };
    std::string name;
    std::string label;         ///< for the panel ("Screen-space error (px)")
    Kind kind = Kind::Number;
    double value = 0.0;        ///< Number, Integer, Toggle
    double min = 0.0, max = 1.0;
    bool logarithmic = false;  ///< a slider over orders of magnitude (budgets, errors)
    std::string choice;        ///< Choice: the current one
    std::vector<std::string> choices;
    std::vector<glm::dvec2> points;   ///< Curve: its control points, sorted by x
    std::vector<glm::vec3> gradient;  ///< Curve: linear RGB along [min, max] to draw behind it
};

class Layer {
public:
    virtual ~Layer() = default;

    virtual std::string_view type() const = 0;

    /// Builds pipelines and GPU resources. Called once, on the main thread, before the first
    /// visible frame, outside any frame recording.
    virtual void prepare(const RenderServices& services) = 0;
    bool prepared() const { return prepared_; }
    void markPrepared() { prepared_ = true; }

    /// First thing in a frame, before the camera modes ask for poses: takes what arrived since
    /// the last frame (a live feed's fixes). Main thread only.
    virtual void poll() {}
    /// Per-frame CPU work (selection, time). Main thread only.
    virtual void update(const FrameContext&) {}
    virtual bool drawsIn(Pass pass) const = 0;
    /// Records uploads and other transfers for this frame, before the first pass begins
    /// (outside any rendering scope). Called only for visible, prepared layers.
    virtual void recordTransfers(const RecordContext&) {}
    /// Records the layer's commands for `pass`. Called while recording, inside the pass.
    virtual void record(Pass pass, const RecordContext& context) = 0;
    /// True when the layer dispatches compute work before `pass` (volume ray casting): then
    /// recordCompute is called after the passes before it, outside any rendering scope, with
    /// the scene depth readable, and record() follows inside the pass (e.g. to composite).
    virtual bool computesBefore(Pass) const { return false; }
    virtual void recordCompute(Pass, const RecordContext&) {}

    /// GPU memory the layer holds, for the stats.
    virtual uint64_t gpuBytes() const { return 0; }
    /// CPU memory the layer holds in caches (tiles, chunks), for the stats.
    virtual uint64_t cacheBytes() const { return 0; }
    /// Items drawn in the last frame (tiles, chunks, ...), for the stats and benchmark tables.
    virtual uint64_t itemsDrawn() const { return 0; }
    /// Sets a numeric quality knob by name (benchmark sweeps: "maxScreenSpaceError", ...).
    /// False when the layer has no such knob.
    virtual bool setParameter(std::string_view /*name*/, double /*value*/) { return false; }
    /// Sets a named setting given as text (a colour map's name, ...), live. False when the
    /// layer has no such setting or the value is not one of its choices.
    virtual bool setOption(std::string_view /*name*/, std::string_view /*value*/) { return false; }
    /// Sets a curve setting (LayerSetting::Kind::Curve: a transfer function's opacity) to these
    /// control points, live. False when the layer has no such setting or the points are not
    /// valid for it (the setting is then unchanged).
    virtual bool setCurve(std::string_view /*name*/, const std::vector<glm::dvec2>& /*points*/) { return false; }
    /// The settings setParameter/setOption take, with their current values, for the viewer's
    /// panel and for saving the scene. Empty for layers without live settings.
    virtual std::vector<LayerSetting> liveSettings() const { return {}; }
    /// Height of the ground (metres above the ellipsoid, as drawn) at a point, for layers that
    /// are ground (terrain); nothing where the layer knows no height. Main thread only.
    virtual std::optional<double> groundHeightAt(double /*lonDeg*/, double /*latDeg*/) const { return std::nullopt; }
    /// Changes whenever groundHeightAt's answers may have changed (tiles loaded or evicted):
    /// layers that sample the ground (FMV's heightfield) resample only then.
    virtual uint64_t groundVersion() const { return 0; }
    /// Distance from `eye` (ECEF) to the nearest content the layer draws (its bounds, 0 when the
    /// eye is inside them), so that the near plane never cuts content floating above the
    /// ground (a point cloud seen from 2 m at 8 000 m). Nothing for layers that are ground
    /// (groundHeightAt covers them) or that need no near plane (ray casting).
    virtual std::optional<double> nearestContent(const glm::dvec3& /*eye*/) const { return std::nullopt; }
    /// The time span of the layer's data (a trajectory's samples), for scenes that give none.
    virtual std::optional<TimeRange> timeRange() const { return std::nullopt; }
    /// The pose of the thing the layer moves at `t` (its first copy) on `ground`, for follow and
    /// pilot cameras; nothing for layers that move nothing or where it is hidden at `t`.
    virtual std::optional<TrackedPose> trackedPose(TimeNs /*t*/, const GroundHeightFn& /*ground*/) const { return std::nullopt; }
    /// Where the layer's moving content goes over its whole time range.
    virtual std::optional<ContentBounds> contentBounds() const { return std::nullopt; }
    /// True while the layer still has work in flight that would change the picture (tiles
    /// loading or waiting for upload). Batch renders wait for it to clear.
    virtual bool busy() const { return false; }
    /// One line for progress and stats ("tiles 120 drawn, 4 loading"); empty when nothing to say.
    virtual std::string status() const { return {}; }

private:
    bool prepared_ = false;
};

}  // namespace orbis::scene
