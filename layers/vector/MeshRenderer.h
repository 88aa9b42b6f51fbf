#pragma once
// Draws a vector layer's 3-D features (FeatureMesh: extruded buildings and polygons at altitude
// as lit triangles, lines and points at altitude as segments and markers) in the Opaque pass:
// each kind's vertices or instances of every chunk in one buffer (GPU memory, uploaded before
// the passes when a new mesh arrives), one pipeline per kind (shaders/vector/mesh.*,
// segment.*, marker.*; shared/VectorTypes.h), made when the first mesh with that kind arrives.
// The chunks in view, above the horizon and within their camera range are drawn: opaque
// triangles first, then translucent surfaces, segments and markers (blended, depth-tested,
// writing no depth). A marker with an icon draws it from an atlas of the layer's icons
// (IconCache's index: cell i holds icon i, fitted, for the first kMeshIconCells^2 of them), made
// with the marker pipeline and filled again when the layer has read more icons. Made only by a
// vector layer that has something in 3-D.

#include "engine/gpu/Buffer.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/Handle.h"
#include "engine/gpu/Image.h"
#include "engine/render/RenderContext.h"
#include "layers/vector/FeatureMesh.h"
#include "layers/vector/IconCache.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace orbis::layers {

class MeshRenderer {
public:
    /// The pipeline layout. `icons`: the layer's icons, which markers name by index (none:
    /// disks only). Main thread, outside recording.
    explicit MeshRenderer(const render::RenderServices& services, std::shared_ptr<vector::IconCache> icons = nullptr);

    /// A new mesh to draw from the next frame on (uploaded in recordTransfers); makes the
    /// pipelines it needs. Main thread, outside recording.
    void setMesh(std::shared_ptr<const vector::FeatureMesh> mesh);
    /// The feature tinted as picked (meshFeatureId), 0: none.
    void setHighlight(uint32_t id) { highlight_ = id; }
    /// This frame's time on the clock of the chunks' glides (MeshChunk::glideEpoch).
    void setGlideClock(double seconds) { glideClock_ = seconds; }

    /// Uploads a new mesh. Called while recording, before the passes.
    void recordTransfers(const render::RecordContext& rc);
    /// Draws the chunks in view. Called while recording, inside the Opaque pass.
    void record(const render::RecordContext& rc);

    uint64_t gpuBytes() const {
        return vertices_.size() + indices_.size() + translucent_.size() + segments_.size() + markers_.size() +
               (atlas_ ? uint64_t(kAtlasPx) * kAtlasPx * 4 : 0);
    }
    uint32_t chunksDrawn() const { return chunksDrawn_; }
    bool hasSegmentPipeline() const { return bool(segmentPipeline_); }

private:
    struct Range {
        uint32_t firstIndex = 0, indexCount = 0, firstTranslucent = 0, translucentCount = 0;
        int32_t vertexOffset = 0;
        uint32_t firstSegment = 0, segmentCount = 0, firstMarker = 0, markerCount = 0;
    };

    static constexpr uint32_t kAtlasPx = shader::kMeshIconCells * shader::kMeshIconCellPx;
    /// Fills the atlas with the icons read so far when there are more than it holds now.
    void refreshAtlas();

    render::RenderServices services_;
    std::shared_ptr<vector::IconCache> icons_;
    gpu::Image atlas_;
    gpu::Sampler sampler_;
    gpu::DescriptorSets sets_;
    std::vector<uint8_t> atlasPixels_;   ///< to upload (empty: nothing new)
    size_t atlasIcons_ = 0;              ///< the icons it holds
    gpu::PipelineLayout layout_;
    gpu::Pipeline meshPipeline_, translucentPipeline_, segmentPipeline_, markerPipeline_;
    std::shared_ptr<const vector::FeatureMesh> mesh_, pending_;
    gpu::Buffer vertices_, indices_, translucent_, segments_, markers_;
    std::vector<Range> ranges_;      ///< per chunk of mesh_
    std::vector<uint32_t> visible_;  ///< this frame's chunks
    uint32_t highlight_ = 0;
    double glideClock_ = 0.0;
    uint32_t chunksDrawn_ = 0;
};

}  // namespace orbis::layers
