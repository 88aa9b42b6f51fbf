#pragma once
// Draws the vector layer's labels (VectorLabels' glyph quads) in the Overlay pass: the glyph
// atlas as an R8 image (what changed uploaded before the passes), one instance buffer per frame
// in flight (host-visible, grown when a frame needs more), and two pipelines over the same
// instances, halos then text (shaders/vector/label.*, shared/VectorTypes.h). Alpha blended, no
// depth test: which labels are hidden was decided on the CPU. Made only by a vector layer whose
// style gives labels.

#include "engine/gpu/Buffer.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/Handle.h"
#include "engine/gpu/Image.h"
#include "shared/VectorTypes.h"

#include <cstdint>
#include <span>
#include <vector>

namespace orbis::render {
struct RenderServices;
struct RecordContext;
}  // namespace orbis::render

namespace orbis::vector {
class GlyphAtlas;
}

namespace orbis::layers {

class LabelRenderer {
public:
    /// The pipelines, the atlas image (`atlasWidth` x `atlasHeight` texels) and its set. Main
    /// thread, outside recording (a layer's onPrepare).
    LabelRenderer(const render::RenderServices& services, int atlasWidth, int atlasHeight);

    /// Uploads what changed in `atlas` (all of it the first time) and this frame's glyphs.
    /// Called while recording, before the passes (recordTransfers).
    void recordTransfers(const render::RecordContext& rc, vector::GlyphAtlas& atlas,
                         std::span<const shader::LabelGlyph> glyphs);
    /// Draws this frame's glyphs. Called while recording, inside the Overlay pass.
    void record(const render::RecordContext& rc);

    uint32_t glyphCount() const { return glyphCount_; }
    uint64_t gpuBytes() const;

private:
    gpu::Device* device_ = nullptr;
    gpu::Image atlas_;
    bool atlasUploaded_ = false;
    gpu::Sampler sampler_;
    gpu::DescriptorSets sets_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline halos_, text_;
    std::vector<gpu::Buffer> instances_;   ///< per frame in flight
    std::vector<uint8_t> staging_;         ///< the atlas rectangle to upload, packed
    uint32_t glyphCount_ = 0;
};

}  // namespace orbis::layers
