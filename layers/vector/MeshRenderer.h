#pragma once
// Draws a vector layer's meshes (FeatureMesh: extruded buildings, polygons at altitude) in the
// Opaque pass: every chunk's vertices and indices in one vertex and one index buffer (GPU
// memory, uploaded before the passes when a new mesh arrives), one pipeline
// (shaders/vector/mesh.*, shared/VectorTypes.h), one draw per chunk that is in view, above the
// horizon and within its camera range. Made only by a vector layer that has meshes to draw.

#include "engine/gpu/Buffer.h"
#include "engine/gpu/Handle.h"
#include "layers/vector/FeatureMesh.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace orbis::render {
struct RenderServices;
struct RecordContext;
}  // namespace orbis::render

namespace orbis::layers {

class MeshRenderer {
public:
    /// The pipeline. Main thread, outside recording.
    explicit MeshRenderer(const render::RenderServices& services);

    /// A new mesh to draw from the next frame on (uploaded in recordTransfers).
    void setMesh(std::shared_ptr<const vector::FeatureMesh> mesh);
    /// The feature tinted as picked (meshFeatureId), 0: none.
    void setHighlight(uint32_t id) { highlight_ = id; }

    /// Uploads a new mesh. Called while recording, before the passes.
    void recordTransfers(const render::RecordContext& rc);
    /// Draws the chunks in view. Called while recording, inside the Opaque pass.
    void record(const render::RecordContext& rc);

    bool empty() const { return !mesh_ || mesh_->chunks.empty(); }
    uint64_t gpuBytes() const { return vertices_.size() + indices_.size(); }
    uint32_t chunksDrawn() const { return chunksDrawn_; }

private:
    struct Range {
        uint32_t firstIndex = 0, indexCount = 0;
        int32_t vertexOffset = 0;
    };

    gpu::Device* device_ = nullptr;
    gpu::PipelineLayout layout_;
    gpu::Pipeline pipeline_;
    std::shared_ptr<const vector::FeatureMesh> mesh_, pending_;
    gpu::Buffer vertices_, indices_;
    std::vector<Range> ranges_;   ///< per chunk of mesh_
    uint32_t highlight_ = 0;
    uint32_t chunksDrawn_ = 0;
};

}  // namespace orbis::layers
