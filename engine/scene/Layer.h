#pragma once
// The interface every kind of content implements (globe, terrain, volume, points, FMV, models,
// pins): prepare once, update each frame, record its passes. What only some layers offer (live
// settings, the ground's height, moving content, content above the ground, statistics) is a
// capability in LayerCapabilities.h that the layer opts into.
//
// A layer is constructed only when the scene names its type, and its GPU objects (pipelines,
// buffers, textures, threads) are made only in prepare(), called before the first frame in
// which the layer is visible: what a scene does not show is never built. No Vulkan here: the
// renderer's services and recording context are engine/render's (RenderContext.h).

#include "engine/scene/FrameContext.h"
#include "engine/scene/LayerCapabilities.h"

#include <string>
#include <string_view>

namespace orbis::render {
struct RenderServices;
struct RecordContext;
}  // namespace orbis::render

namespace orbis::scene {

class Layer {
public:
    virtual ~Layer() = default;

    virtual std::string_view type() const = 0;

    /// Builds pipelines and GPU resources (onPrepare). Called once, on the main thread, before
    /// the first visible frame, outside any frame recording.
    void prepare(const render::RenderServices& services) {
        onPrepare(services);
        prepared_ = true;
    }
    bool prepared() const { return prepared_; }

    /// First thing in a frame, before the camera modes ask for poses: takes what arrived since
    /// the last frame (a live feed's fixes). Main thread only.
    virtual void poll() {}
    /// Per-frame CPU work (selection, time). Main thread only.
    virtual void update(const FrameContext&) {}

    // Recording, in the order the renderer calls it. Only for visible, prepared layers.
    virtual bool drawsIn(Pass pass) const = 0;
    /// True when the layer dispatches compute work before `pass` (volume ray casting): then
    /// recordCompute is called after the passes before it, outside any rendering scope, with
    /// the scene depth readable, and record() follows inside the pass (e.g. to composite).
    virtual bool computesBefore(Pass) const { return false; }
    /// Records uploads and other transfers for this frame, before the first pass begins
    /// (outside any rendering scope).
    virtual void recordTransfers(const render::RecordContext&) {}
    virtual void recordCompute(Pass, const render::RecordContext&) {}
    /// Records the layer's commands for `pass`. Called while recording, inside the pass.
    virtual void record(Pass pass, const render::RecordContext& context) = 0;

    /// True while the layer still has work in flight that would change the picture (tiles
    /// loading or waiting for upload). Batch renders wait for it to clear.
    virtual bool busy() const { return false; }
    /// One line for progress and stats ("tiles 120 drawn, 4 loading"); empty when nothing to say.
    virtual std::string status() const { return {}; }

    // Capabilities (LayerCapabilities.h): the layer itself when it has one, else null.
    virtual LiveSettings* asLiveSettings() { return nullptr; }
    const LiveSettings* asLiveSettings() const { return const_cast<Layer*>(this)->asLiveSettings(); }
    virtual const GroundSource* asGroundSource() const { return nullptr; }
    virtual const MovingContent* asMovingContent() const { return nullptr; }
    virtual const FloatingContent* asFloatingContent() const { return nullptr; }
    virtual const DrapedContent* asDrapedContent() const { return nullptr; }
    virtual PickableContent* asPickable() { return nullptr; }
    virtual const LayerStats* asStats() const { return nullptr; }
    virtual const LiveFeed* asLiveFeed() const { return nullptr; }

protected:
    /// The layer's part of prepare().
    virtual void onPrepare(const render::RenderServices& services) = 0;

private:
    bool prepared_ = false;
};

}  // namespace orbis::scene
