#include "layers/terrain/TerrainLayer.h"

#include "base/Color.h"
#include "base/Log.h"
#include "base/ThreadPool.h"
#include "engine/gpu/Barriers.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Pipeline.h"
#include "engine/gpu/Uploader.h"
#include "engine/gpu/VkCheck.h"
#include "engine/render/RenderContext.h"
#include "engine/render/SkyPipeline.h"
#include "globe/Ellipsoid.h"
#include "globe/TileMesh.h"
#include "shared/TerrainTypes.h"

#include "spv/terrain/terrain.frag.h"
#include "spv/terrain/terrain.vert.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace orbis::layers {
namespace {

constexpr uint32_t kMeshLayer = 0xffffffffu;   // DataKey layer used for tile meshes
constexpr uint32_t kMeshSlotsPerPage = 64;
constexpr uint32_t kMeshPagesMax = 64;
enum Kind : uint32_t { kMesh = 0, kElevation = 1, kImagery = 2 };

}  // namespace

TerrainLayer::TerrainLayer(TerrainSettings settings) : settings_(std::move(settings)) {}

TerrainLayer::~TerrainLayer() = default;

void TerrainLayer::onPrepare(const render::RenderServices& services) {
    services_ = services;
    gpu::Device& device = *services.device;

    // Sources: a bad one is reported and left out; the terrain draws without it.
    std::vector<std::shared_ptr<globe::RasterSource>> dems, images;
    for (const auto& o : settings_.elevation) {
        auto s = globe::RasterSource::open(o);
        if (s) dems.push_back(*s);
        else errors_.push_back(s.message()), log::error(s.message());
    }
    imageryIndex_.clear();
    for (size_t i = 0; i < settings_.imagery.size(); ++i) {
        auto s = globe::RasterSource::open(settings_.imagery[i].source);
        if (s) {
            images.push_back(*s);
            imageryIndex_.push_back(i);
        } else {
            errors_.push_back(s.message()), log::error(s.message());
        }
    }
    globe::TerrainModelSettings ms;
    ms.gridSize = settings_.gridSize;
    ms.imageSize = settings_.imageSize;
    ms.cpuBudgetBytes = settings_.cpuCacheBytes;
    ms.maxLevel = settings_.maxLevel;
    ground_ = std::make_unique<TerrainGround>(settings_.gridSize, settings_.maxLevel, dems);
    // No sources, no threads: the pool starts only when there is something to load.
    jobs::ThreadPool* pool = dems.empty() && images.empty() ? nullptr : &services.jobs();
    model_ = std::make_unique<globe::TerrainModel>(ms, std::move(dems), std::move(images), pool);
    globe::SelectorSettings sel;
    sel.maxScreenSpaceError = settings_.maxScreenSpaceError;
    sel.maxLevel = settings_.maxLevel;
    sel.gridSize = settings_.gridSize;
    sel.detailLevel = 0;   // no sources: the ellipsoid's curvature alone sets the error
    for (uint32_t l = 0; l < model_->layerCount(); ++l)
        if (l > 0 || model_->hasElevation()) sel.detailLevel = std::max(sel.detailLevel, model_->maxDataLevel(l));
    selector_ = std::make_unique<globe::TileSelector>(sel);

    // Residency pools: pages are allocated on demand, up to the GPU budget.
    const int n = settings_.gridSize;
    meshes_.slotsPerPage = kMeshSlotsPerPage;
    meshes_.maxPages = kMeshPagesMax;
    meshes_.pageBytes = uint64_t(kMeshSlotsPerPage) * globe::tileVertexCount(n) * sizeof(globe::TileVertex);
    elevation_.slotsPerPage = shader::kElevationSlotsPerPage;
    elevation_.maxPages = shader::kElevationPages;
    elevation_.pageBytes = uint64_t(shader::kElevationSlotsPerPage) * n * n * 4 * sizeof(float);
    imagery_.slotsPerPage = shader::kImagerySlotsPerPage;
    imagery_.maxPages = shader::kImageryPages;
    imagery_.pageBytes = uint64_t(shader::kImagerySlotsPerPage) * settings_.imageSize * settings_.imageSize * 4 * 4 / 3;

    const std::vector<uint32_t> indices = globe::buildTileIndices(n);
    indexCount_ = uint32_t(indices.size());
    indices_ = gpu::Buffer(device, indices.size() * sizeof(uint32_t),
                           VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::GpuOnly,
                           "terrain indices");
    gpu::ImageDesc de;
    de.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
    de.format = VK_FORMAT_R32G32B32A32_SFLOAT;   // height, gradient east, gradient south
    de.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    de.extent = {uint32_t(n), uint32_t(n), 1};
    de.name = "terrain elevation (unused page)";
    dummyElevation_ = gpu::Image(device, de);
    gpu::ImageDesc di = de;
    di.format = VK_FORMAT_R8G8B8A8_SRGB;
    di.extent = {1, 1, 1};
    di.name = "terrain imagery (unused page)";
    dummyImagery_ = gpu::Image(device, di);
    device.runOnce([&](VkCommandBuffer cmd) {
        services.uploader->toBuffer(cmd, indices_, indices.data(), indices.size() * sizeof(uint32_t));
        gpu::bufferBarrier(cmd, indices_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, VK_ACCESS_2_INDEX_READ_BIT);
        const std::vector<float> zeros(size_t(n) * size_t(n) * 4, 0.0f);
        services.uploader->toImage(cmd, dummyElevation_, zeros.data(), zeros.size() * sizeof(float));
        const uint8_t clear[4] = {0, 0, 0, 0};
        services.uploader->toImage(cmd, dummyImagery_, clear, 4);
        gpu::transition(cmd, dummyElevation_, gpu::ImageUse::SampledGraphics);
        gpu::transition(cmd, dummyImagery_, gpu::ImageUse::SampledGraphics);
    });

    heightSampler_ = gpu::createSampler(device, {});
    // Anisotropic filtering where it helps (createSampler leaves it off on CPU devices).
    imagerySampler_ = gpu::createSampler(device, {.mipmaps = true, .maxAnisotropy = 4.0f});

    const uint32_t frames = services.framesInFlight;
    descriptors_ = gpu::createDescriptorSets(device, shader::kTerrainBindings, frames);
    setVersion_.assign(frames, 0);
    for (uint32_t f = 0; f < frames; ++f) {
        drawBuffers_.emplace_back(device, uint64_t(maxDraws_) * sizeof(shader::TileDraw),
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::Upload, "terrain draws");
    }

    const VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                   sizeof(shader::TerrainPush)};
    const VkDescriptorSetLayout sets[] = {services.frameSetLayout, descriptors_.layout.vk()};
    layout_ = gpu::createPipelineLayout(device, sets, {&push, 1});

    gpu::GraphicsPipelineDesc surface;
    surface.vertexSpirv = kSpv_terrain_terrain_vert;
    surface.fragmentSpirv = kSpv_terrain_terrain_frag;
    surface.layout = layout_.vk();
    surface.bindings = {{0, sizeof(globe::TileVertex), VK_VERTEX_INPUT_RATE_VERTEX}};
    surface.attributes = {
        {shader::kTerrainInputPosition, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(globe::TileVertex, position)},
        {shader::kTerrainInputNormal, 0, VK_FORMAT_R16G16B16A16_SNORM, offsetof(globe::TileVertex, normal)},
        {shader::kTerrainInputUv, 0, VK_FORMAT_R16G16_UNORM, offsetof(globe::TileVertex, uv)},
        {shader::kTerrainInputCellMetres, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(globe::TileVertex, cellMetres)}};
    surface.cullMode = VK_CULL_MODE_NONE;   // skirts face both ways; hidden faces lose the depth test
    gpu::Specialization spec;
    spec.set<int32_t>(shader::kTerrainSpecImageryLayers, int32_t(imageryIndex_.size()));
    surface.specialization = &spec;
    surface.colorFormat = services.colorFormat;
    surface.depthFormat = services.depthFormat;
    surface.name = "terrain surface";
    surface_ = gpu::createGraphicsPipeline(device, surface);

    if (settings_.sky) sky_ = render::createSkyPipeline(device, layout_.vk(), services, "terrain sky");
}

uint64_t TerrainLayer::allocatedBytes() const {
    return uint64_t(meshes_.pages()) * meshes_.pageBytes + uint64_t(elevation_.pages()) * elevation_.pageBytes +
           uint64_t(imagery_.pages()) * imagery_.pageBytes;
}

void TerrainLayer::addPage(uint32_t kind) {
    gpu::Device& device = *services_.device;
    SlotPool& pool = kind == kMesh ? meshes_ : kind == kElevation ? elevation_ : imagery_;
    const uint32_t first = uint32_t(pool.slots.size());
    pool.slots.resize(pool.slots.size() + pool.slotsPerPage);
    for (uint32_t i = pool.slotsPerPage; i-- > 0;) pool.freeSlots.push_back(first + i);
    if (kind == kMesh) {
        meshPages_.emplace_back(device, pool.pageBytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                gpu::MemoryUsage::GpuOnly, "terrain meshes");
        return;
    }
    gpu::ImageDesc d;
    d.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
    d.layers = pool.slotsPerPage;
    d.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    if (kind == kElevation) {
        d.format = VK_FORMAT_R32G32B32A32_SFLOAT;
        d.extent = {uint32_t(settings_.gridSize), uint32_t(settings_.gridSize), 1};
        d.name = "terrain elevation page";
        elevationPages_.emplace_back(device, d);
    } else {
        d.format = VK_FORMAT_R8G8B8A8_SRGB;
        d.extent = {uint32_t(settings_.imageSize), uint32_t(settings_.imageSize), 1};
        d.mipLevels = uint32_t(std::log2(settings_.imageSize)) + 1;
        d.name = "terrain imagery page";
        imageryPages_.emplace_back(device, d);
    }
    ++descriptorVersion_;
}

std::optional<uint32_t> TerrainLayer::acquireSlot(SlotPool& pool, const globe::DataKey& owner, bool mayExceedBudget) {
    const uint32_t kind = &pool == &meshes_ ? kMesh : &pool == &elevation_ ? kElevation : kImagery;
    if (pool.freeSlots.empty()) {
        // Grow while within the budget; then reuse the least recently used slot that this frame
        // does not need; only a mesh (without which a tile would be a hole) may go over.
        const bool fits = fixedBytes() + allocatedBytes() + pool.pageBytes <= settings_.gpuCacheBytes;
        uint32_t victim = UINT32_MAX;
        if (!(fits && pool.pages() < pool.maxPages)) {
            uint64_t oldest = UINT64_MAX;
            for (uint32_t i = 0; i < pool.slots.size(); ++i) {
                const Slot& slot = pool.slots[i];
                if (slot.lastUsed < frame_ && slot.lastUsed < oldest) victim = i, oldest = slot.lastUsed;
            }
        }
        if (victim != UINT32_MAX) {
            pool.resident.erase(pool.slots[victim].owner);
            pool.slots[victim].taken = false;
            pool.freeSlots.push_back(victim);
        } else if (pool.pages() < pool.maxPages && (fits || mayExceedBudget || pool.pages() == 0)) {
            if (!fits && !warnedBudget_) {
                warnedBudget_ = true;
                log::warn("terrain: this view needs more than the GPU tile budget (", settings_.gpuCacheBytes >> 20,
                          " MB); raise \"gpuCacheMB\" or \"maxScreenSpaceError\"");
            }
            addPage(kind);
        } else {
            return std::nullopt;   // the caller falls back to an ancestor already on the GPU
        }
    }
    const uint32_t slot = pool.freeSlots.back();
    pool.freeSlots.pop_back();
    pool.slots[slot] = Slot{owner, frame_, true};
    pool.resident[owner] = slot;
    return slot;
}

void TerrainLayer::update(const scene::FrameContext& frame) {
    frame_ = frame.frameNumber + 1;   // 0 means "never used"
    const scene::Camera& camera = *frame.camera;
    model_->beginFrame(frame_);
    ground_->endFrame();
    stats_ = {};

    const double ex = settings_.verticalExaggeration;
    globe::SelectorView view;
    view.eye = camera.position();
    view.worldToView = glm::dmat3(camera.viewRotation());
    view.fovYRad = camera.verticalFovRad();
    view.aspect = frame.aspect();
    view.nearPlane = camera.nearPlane();
    view.viewportHeightPx = frame.height;
    const auto heights = [&](const globe::TileKey& k) {
        const globe::TileHeightRange r = model_->heightRange(k);
        return globe::TileHeightRange{std::min(r.minHeight * ex, 0.0), std::max(r.maxHeight * ex, 0.0)};
    };
    const auto& selected = selector_->select(view, heights);
    stats_.selection = selector_->stats();

    // Ask for data: elevation and each visible imagery layer, near and coarse first.
    for (const auto& t : selected) {
        model_->request(0, t.key, t.distance);
        for (uint32_t i = 0; i < imageryIndex_.size(); ++i)
            if (settings_.imagery[imageryIndex_[i]].visible) model_->request(1 + i, t.key, t.distance);
    }
    model_->endFrame();

    // Residency and the draw list.
    uploads_.clear();
    uint64_t uploadBytes = 0;
    deferred_ = false;
    const uint64_t elevBytes = uint64_t(settings_.gridSize) * settings_.gridSize * 4 * sizeof(float);
    const uint64_t imgBytes = uint64_t(settings_.imageSize) * settings_.imageSize * 4 * 4 / 3;
    const auto resident = [&](SlotPool& pool, uint32_t kind, uint32_t layer, const globe::TileKey& tile,
                              uint64_t bytes) -> std::optional<std::pair<globe::TileKey, uint32_t>> {
        // The deepest ready ancestor-or-self that is on the GPU or can go there this frame.
        std::optional<globe::TileKey> a = model_->readyAncestor(layer, tile);
        while (a) {
            const globe::DataKey key{layer, *a};
            if (auto it = pool.resident.find(key); it != pool.resident.end()) {
                pool.slots[it->second].lastUsed = frame_;
                return std::make_pair(*a, it->second);
            }
            if (uploadBytes + bytes <= settings_.uploadBudgetBytes) {
                if (auto slot = acquireSlot(pool, key, false)) {
                    uploads_.push_back({kind, *slot, *a, layer});
                    uploadBytes += bytes;
                    return std::make_pair(*a, *slot);
                }
            } else {
                deferred_ = true;
            }
            if (a->level == 0) break;
            a = model_->readyAncestor(layer, a->parent());
        }
        return std::nullopt;
    };

    const glm::dmat4 proj = camera.projection(frame.aspect());
    const auto& ell = globe::Ellipsoid::wgs84();
    const size_t count = std::min<size_t>(selected.size(), maxDraws_);
    if (selected.size() > maxDraws_ && !warnedDrawCap_) {
        warnedDrawCap_ = true;
        log::warn("terrain: ", selected.size(), " tiles selected, drawing the first ", maxDraws_,
                  "; raise \"maxScreenSpaceError\"");
    }
    drawItems_.clear();
    drawData_.resize(count * sizeof(shader::TileDraw));
    for (size_t i = 0; i < count; ++i) {
        const globe::TileKey key = selected[i].key;
        const globe::DataKey meshKey{kMeshLayer, key};
        uint32_t meshSlot;
        if (auto it = meshes_.resident.find(meshKey); it != meshes_.resident.end()) {
            meshSlot = it->second;
            meshes_.slots[meshSlot].lastUsed = frame_;
        } else {
            // Meshes are never held back: without one, the tile would be a hole.
            auto slot = acquireSlot(meshes_, meshKey, true);
            if (!slot) continue;
            meshSlot = *slot;
            uploads_.push_back({kMesh, meshSlot, key, kMeshLayer});
            uploadBytes += meshes_.pageBytes / meshes_.slotsPerPage;
        }
        const globe::GeoExtent e = key.extent();
        const glm::dvec3 center = ell.toEcef(e.centerLon(), e.centerLat(), 0.0);

        shader::TileDraw d{};
        d.modelViewProj = glm::mat4(proj * camera.modelViewRelativeToEye(center));
        const double cell = key.sizeDeg() * 111320.0 / double(settings_.gridSize - 1);
        const globe::TileHeightRange hr = heights(key);
        // Deep enough for the gap between a tile and a coarser neighbour: the chord sag of the
        // coarser grid (twice this cell) plus part of the height range; any deeper only costs
        // fill rate where skirts show at grazing angles.
        const double sag = (2.0 * cell) * (2.0 * cell) / (8.0 * 6371000.0);
        const double skirt = std::min(sag + 0.25 * (hr.maxHeight - hr.minHeight), 5.0e4) + 10.0;
        d.originFromEye = glm::vec3(center - camera.position());
        d.skirtDepth = float(skirt);
        d.elevationSlot = -1;
        d.elevationGridSize = settings_.gridSize;
        d.elevationScaleBias = glm::vec4(1, 1, 0, 0);
        if (auto r = resident(elevation_, kElevation, 0, key, elevBytes)) {
            d.elevationSlot = int(r->second);
            d.elevationScaleBias = glm::vec4(key.scaleBiasWithin(r->first));
            if (r->first == key) ++stats_.tilesWithOwnElevation;
        }
        d.imagerySlot = glm::ivec4(-1);
        for (uint32_t l = 0; l < imageryIndex_.size(); ++l) {
            d.imageryScaleBias[l] = glm::vec4(1, 1, 0, 0);
            if (!settings_.imagery[imageryIndex_[l]].visible) continue;
            if (auto r = resident(imagery_, kImagery, 1 + l, key, imgBytes)) {
                d.imagerySlot[int(l)] = int(r->second);
                d.imageryScaleBias[l] = glm::vec4(key.scaleBiasWithin(r->first));
            }
        }
        const uint32_t drawIndex = uint32_t(drawItems_.size());
        std::memcpy(drawData_.data() + drawIndex * sizeof(d), &d, sizeof(d));
        drawItems_.push_back({meshSlot, drawIndex, selected[i].distance});
        stats_.deepestLevel = std::max(stats_.deepestLevel, key.level);
    }
    drawData_.resize(drawItems_.size() * sizeof(shader::TileDraw));
    // Front to back (the selection's distance), so the depth test rejects hidden terrain
    // before it is shaded; vertex buffers are rebound only when the page changes.
    std::stable_sort(drawItems_.begin(), drawItems_.end(),
                     [](const DrawItem& a, const DrawItem& b) { return a.distance < b.distance; });
    stats_.tilesDrawn = drawItems_.size();
    stats_.uploadsThisFrame = uploads_.size();
    stats_.uploadBytesThisFrame = uploadBytes;
    for (const auto& err : model_->errors())
        if (std::find(errors_.begin(), errors_.end(), err) == errors_.end()) errors_.push_back(err);
}

void TerrainLayer::writeDescriptors(uint32_t f) {
    if (setVersion_[f] == descriptorVersion_) return;
    setVersion_[f] = descriptorVersion_;
    // Pages not made yet are bound to a dummy: the shaders index every page.
    std::vector<VkImageView> elev(shader::kElevationPages), img(shader::kImageryPages);
    for (uint32_t i = 0; i < elev.size(); ++i)
        elev[i] = i < elevationPages_.size() ? elevationPages_[i].view() : dummyElevation_.view();
    for (uint32_t i = 0; i < img.size(); ++i) img[i] = i < imageryPages_.size() ? imageryPages_[i].view() : dummyImagery_.view();
    gpu::DescriptorWriter(descriptors_.sets[f])
        .storageBuffer(shader::kTerrainBindingDraws, drawBuffers_[f])
        .sampledImages(shader::kTerrainBindingElevation, heightSampler_.vk(), elev)
        .sampledImages(shader::kTerrainBindingImagery, imagerySampler_.vk(), img)
        .update(*services_.device);
}

void TerrainLayer::recordTransfers(const render::RecordContext& rc) {
    VkCommandBuffer cmd = rc.cmd;
    if (!drawData_.empty()) drawBuffers_[rc.slot].write(drawData_.data(), drawData_.size());
    if (!uploads_.empty()) {
        // Slots may be reused: earlier frames' reads of them come before these writes.
        VkMemoryBarrier2 before{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
        before.srcStageMask = VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT;
        before.dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
        VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
        dep.memoryBarrierCount = 1;
        dep.pMemoryBarriers = &before;
        vkCmdPipelineBarrier2(cmd, &dep);

        const int n = settings_.gridSize;
        std::vector<bool> meshTouched(meshPages_.size()), elevTouched(elevationPages_.size()),
            imgTouched(imageryPages_.size());
        for (const PendingUpload& u : uploads_) {
            if (u.kind == kMesh) {
                const globe::TileMesh mesh = globe::buildTileMesh(u.tile, n);
                const uint32_t page = u.slot / kMeshSlotsPerPage, index = u.slot % kMeshSlotsPerPage;
                const VkDeviceSize bytes = mesh.vertices.size() * sizeof(globe::TileVertex);
                rc.uploader->toBuffer(cmd, meshPages_[page], mesh.vertices.data(), bytes, index * bytes);
                meshTouched[page] = true;
            } else if (u.kind == kElevation) {
                const auto data = model_->elevation(u.tile);
                const uint32_t page = u.slot / shader::kElevationSlotsPerPage;
                // Height and its gradient per sample (computed by the loader): interpolating
                // the gradient gives continuous normals.
                const auto& h = data->heights;
                std::vector<float> texels(h.size() * 4);
                for (size_t i = 0; i < h.size(); ++i) {
                    texels[i * 4] = h[i];
                    texels[i * 4 + 1] = data->gradients[i * 2];
                    texels[i * 4 + 2] = data->gradients[i * 2 + 1];
                    texels[i * 4 + 3] = 0.0f;
                }
                rc.uploader->toImage(cmd, elevationPages_[page], texels.data(), texels.size() * sizeof(float),
                                     u.slot % shader::kElevationSlotsPerPage);
                elevTouched[page] = true;
            } else {
                const auto data = model_->imagery(u.layer, u.tile);
                const uint32_t page = u.slot / shader::kImagerySlotsPerPage;
                std::vector<VkBufferImageCopy> regions;
                for (int m = 0; m < data->mipLevels(); ++m) {
                    const uint32_t size = uint32_t(std::max(data->size >> m, 1));
                    VkBufferImageCopy r{};
                    r.bufferOffset = data->mipOffsets[size_t(m)];
                    r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), u.slot % shader::kImagerySlotsPerPage, 1};
                    r.imageExtent = {size, size, 1};
                    regions.push_back(r);
                }
                rc.uploader->toImageRegions(cmd, imageryPages_[page], data->rgba.data(), data->rgba.size(), regions);
                imgTouched[page] = true;
            }
        }
        for (size_t p = 0; p < meshPages_.size(); ++p)
            if (meshTouched[p])
                gpu::bufferBarrier(cmd, meshPages_[p], VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                   VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT);
        for (size_t p = 0; p < elevationPages_.size(); ++p)
            if (elevTouched[p]) gpu::transition(cmd, elevationPages_[p], gpu::ImageUse::SampledGraphics);
        for (size_t p = 0; p < imageryPages_.size(); ++p)
            if (imgTouched[p]) gpu::transition(cmd, imageryPages_[p], gpu::ImageUse::SampledGraphics);
        uploads_.clear();
    }
    writeDescriptors(rc.slot);
}

void TerrainLayer::record(scene::Pass, const render::RecordContext& rc) {
    VkCommandBuffer cmd = rc.cmd;
    const VkDescriptorSet sets[] = {rc.frameSet, descriptors_.sets[rc.slot]};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), 0, 2, sets, 0, nullptr);
    shader::TerrainPush push{};
    push.baseColor = glm::vec3(srgbToLinear(settings_.color.r), srgbToLinear(settings_.color.g), srgbToLinear(settings_.color.b));
    push.verticalExaggeration = float(settings_.verticalExaggeration);
    for (uint32_t l = 0; l < imageryIndex_.size(); ++l)
        push.imageryOpacity[int(l)] = float(settings_.imagery[imageryIndex_[l]].opacity);
    push.sunLighting = settings_.sunLighting ? 1u : 0u;
    push.tileBorders = settings_.tileBorders ? 1u : 0u;
    push.imageSizePx = float(settings_.imageSize);
    const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    vkCmdPushConstants(cmd, layout_.vk(), stages, 0, sizeof(push), &push);

    if (!drawItems_.empty()) drawSurface(cmd);
    if (sky_) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, sky_.vk());
        vkCmdDraw(cmd, 3, 1, 0, 0);
    }
}

void TerrainLayer::drawSurface(VkCommandBuffer cmd) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, surface_.vk());
    vkCmdBindIndexBuffer(cmd, indices_.vk(), 0, VK_INDEX_TYPE_UINT32);
    const uint32_t verts = globe::tileVertexCount(settings_.gridSize);
    uint32_t boundPage = UINT32_MAX;
    for (const DrawItem& item : drawItems_) {
        const uint32_t page = item.meshSlot / kMeshSlotsPerPage;
        if (page != boundPage) {
            const VkBuffer vb = meshPages_[page].vk();
            const VkDeviceSize offset = 0;
            vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
            boundPage = page;
        }
        vkCmdDrawIndexed(cmd, indexCount_, 1, 0, int32_t((item.meshSlot % kMeshSlotsPerPage) * verts), item.drawIndex);
    }
}

uint64_t TerrainLayer::fixedBytes() const {
    uint64_t bytes = indices_.size();
    for (const auto& b : drawBuffers_) bytes += b.size();
    return bytes;
}

uint64_t TerrainLayer::gpuBytes() const { return fixedBytes() + allocatedBytes(); }

bool TerrainLayer::setParameter(std::string_view name, double value) {
    // The ranges the scene file accepts (create()), so that a saved scene loads again.
    if (name == "maxScreenSpaceError" && value >= 0.25 && value <= 1000.0) {
        settings_.maxScreenSpaceError = value;
        if (selector_) {
            globe::SelectorSettings s = selector_->settings();
            s.maxScreenSpaceError = value;
            selector_->setSettings(s);
            selector_->reset();
        }
        return true;
    }
    if (name == "verticalExaggeration" && value >= 0.0 && value <= 1000.0) {
        if (value != settings_.verticalExaggeration) ++groundChanges_;
        settings_.verticalExaggeration = value;
        return true;
    }
    // Imagery layer i (the scene's "imagery"[i]): its opacity over the layers under it, and
    // whether it is drawn (and loaded) at all.
    const auto imageryIndex = [&](std::string_view prefix) -> std::optional<size_t> {
        if (name.size() <= prefix.size() || name.substr(0, prefix.size()) != prefix) return std::nullopt;
        size_t i = 0;
        for (char c : name.substr(prefix.size())) {
            if (c < '0' || c > '9' || i > settings_.imagery.size()) return std::nullopt;
            i = i * 10 + size_t(c - '0');
        }
        return i < settings_.imagery.size() ? std::optional<size_t>(i) : std::nullopt;
    };
    if (const auto i = imageryIndex("imageryOpacity"); i && value >= 0.0 && value <= 1.0) {
        settings_.imagery[*i].opacity = value;
        return true;
    }
    if (const auto i = imageryIndex("imageryVisible"); i && (value == 0.0 || value == 1.0)) {
        settings_.imagery[*i].visible = value != 0.0;
        return true;
    }
    return false;
}

std::vector<scene::LayerSetting> TerrainLayer::liveSettings() const {
    using Kind = scene::LayerSetting::Kind;
    std::vector<scene::LayerSetting> out = {
        {.name = "maxScreenSpaceError", .label = "Screen-space error (px)", .kind = Kind::Number,
         .value = settings_.maxScreenSpaceError, .min = 0.25, .max = 1000.0, .logarithmic = true},
        {.name = "verticalExaggeration", .label = "Vertical exaggeration", .kind = Kind::Number,
         .value = settings_.verticalExaggeration, .min = 0.0, .max = 1000.0, .logarithmic = true},
    };
    for (size_t i = 0; i < settings_.imagery.size(); ++i) {
        const ImageryLayerSettings& l = settings_.imagery[i];
        const std::string name = l.name.empty() ? "Imagery " + std::to_string(i + 1) : l.name;
        out.push_back({.name = "imageryVisible" + std::to_string(i), .label = name, .kind = Kind::Toggle,
                       .value = l.visible ? 1.0 : 0.0});
        out.push_back({.name = "imageryOpacity" + std::to_string(i), .label = name + " opacity", .kind = Kind::Number,
                       .value = l.opacity, .min = 0.0, .max = 1.0});
    }
    return out;
}

bool TerrainLayer::busy() const { return (model_ && model_->loading()) || deferred_; }

std::string TerrainLayer::status() const {
    std::ostringstream s;
    s << "tiles " << stats_.tilesDrawn << " drawn (deepest level " << stats_.deepestLevel << ")";
    if (model_) {
        s << ", " << model_->stats().loading << " loading, " << (model_->cpuBytes() >> 20) << " MB cached";
    }
    s << ", " << (gpuBytes() >> 20) << " MB on the GPU";
    if (!errors_.empty()) s << ", " << errors_.size() << " error(s)";
    return s.str();
}

std::optional<double> TerrainLayer::heightAt(double lonDeg, double latDeg) const {
    if (!ground_) return std::nullopt;
    auto h = ground_->heightAt(lonDeg, latDeg);
    if (h) *h *= settings_.verticalExaggeration;
    return h;
}

}  // namespace orbis::layers
