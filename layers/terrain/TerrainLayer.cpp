#include "layers/terrain/TerrainLayer.h"

#include <chrono>
#include <cstdio>

#include "base/Color.h"
#include "base/Log.h"
#include "base/ThreadPool.h"
#include "engine/gpu/Barriers.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Pipeline.h"
#include "engine/gpu/Uploader.h"
#include "engine/render/RenderContext.h"
#include "engine/render/SkyPipeline.h"
#include "globe/Ellipsoid.h"
#include "globe/TileMesh.h"
#include "shared/FrameUniforms.h"
#include "shared/TerrainTypes.h"

#include "spv/terrain/terrain.frag.h"
#include "spv/terrain/terrain.vert.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace orbis::layers {

// The pipeline layouts list the sets in order: the frame's, then the layer's.
static_assert(shader::kTerrainSet == shader::kFrameSet + 1);

namespace {

constexpr uint32_t kMeshLayer = 0xffffffffu;   // DataKey layer used for tile meshes
using Kind = TileSlotPool::Kind;

}  // namespace

TerrainLayer::TerrainLayer(TerrainSettings settings) : settings_(std::move(settings)) {}

TerrainLayer::~TerrainLayer() = default;

void TerrainLayer::onPrepare(const render::RenderServices& services) {
    services_ = services;
    openSources(services);
    createGpuObjects(services);
    buildPipelines(services);
}

void TerrainLayer::openSources(const render::RenderServices& services) {
    // Sources: a bad one is reported and left out; the terrain draws without it.
    std::vector<std::shared_ptr<globe::RasterSource>> dems;
    std::vector<std::shared_ptr<const globe::TileImageSource>> images;
    for (const auto& o : settings_.elevation) {
        auto s = globe::RasterSource::open(o);
        if (s) dems.push_back(*s);
        else errors_.push_back(s.message()), log::error(s.message());
    }
    imageryIndex_.clear();
    timeShown_.clear();
    for (size_t i = 0; i < settings_.imagery.size(); ++i) {
        // A time-enabled layer opens at its first value; the first frame moves it to the scene's.
        const auto& layer = settings_.imagery[i];
        auto s = globe::RasterSource::open(layer.times.empty() ? layer.source : atWmsTime(layer.source, layer.times[0]));
        if (s) {
            images.push_back(*s);
            imageryIndex_.push_back(i);
            timeShown_.push_back(0);
        } else {
            errors_.push_back(s.message()), log::error(s.message());
        }
    }
    globe::TerrainTilesSettings ts;
    ts.gridSize = settings_.gridSize;
    ts.imageSize = settings_.imageSize;
    ts.cpuBudgetBytes = settings_.cpuCacheBytes;
    ts.maxLevel = settings_.maxLevel;
    // Tiles are refined while a quarter grid cell spans more than maxScreenSpaceError pixels
    // at the tile's nearest point, so an image texel (imageSize texels over gridSize - 1 cells)
    // spans at most that many pixels there, and about half that over most of the tile (measured:
    // a 3-texel line over flat ground is about 3 px wide at the default 2 px).
    ts.tilePixelsPerScreenPixel = 2.0 / settings_.maxScreenSpaceError *
                                  (double(settings_.imageSize) / (4.0 * double(settings_.gridSize - 1)));
    ground_ = std::make_shared<TerrainGround>(settings_.gridSize, settings_.maxLevel, dems);
    // No sources, no threads: the pool starts only when there is something to load (a drape
    // added later starts it then).
    jobs::ThreadPool* pool = dems.empty() && images.empty() ? nullptr : &services.jobs();
    tiles_ = std::make_unique<globe::TerrainTiles>(ts, std::move(dems), std::move(images), pool);
    globe::SelectorSettings sel;
    sel.maxScreenSpaceError = settings_.maxScreenSpaceError;
    sel.maxLevel = settings_.maxLevel;
    sel.gridSize = settings_.gridSize;
    sel.detailLevel = 0;   // no sources: the ellipsoid's curvature alone sets the error
    for (uint32_t l = 0; l < tiles_->layerCount(); ++l)
        if (l > 0 || tiles_->hasElevation()) sel.detailLevel = std::max(sel.detailLevel, tiles_->maxDataLevel(l));
    selector_ = std::make_unique<globe::TileSelector>(sel);
}

void TerrainLayer::createGpuObjects(const render::RenderServices& services) {
    gpu::Device& device = *services.device;
    const std::vector<uint32_t> indices = globe::buildTileIndices(settings_.gridSize);
    indexCount_ = uint32_t(indices.size());
    indices_ = gpu::Buffer(device, indices.size() * sizeof(uint32_t),
                           VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::GpuOnly,
                           "terrain indices");
    device.runOnce([&](VkCommandBuffer cmd) {
        services.uploader->toBuffer(cmd, indices_, indices.data(), indices.size() * sizeof(uint32_t));
        gpu::bufferBarrier(cmd, indices_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, VK_ACCESS_2_INDEX_READ_BIT);
    });
    const uint32_t frames = services.framesInFlight;
    descriptors_ = gpu::createDescriptorSets(device, shader::kTerrainBindings, frames);
    setVersion_.assign(frames, 0);
    for (uint32_t f = 0; f < frames; ++f) {
        drawBuffers_.emplace_back(device, uint64_t(maxDraws_) * sizeof(shader::TileDraw),
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::Upload, "terrain draws");
    }
    // Tile data: pages are allocated on demand, up to the GPU budget less the buffers above.
    gpuSlots_ = std::make_unique<TileSlotPool>(device, *services.uploader, settings_.gridSize, settings_.imageSize,
                                               settings_.gpuCacheBytes, fixedBytes());
    heightSampler_ = gpu::createSampler(device, {});
    // Anisotropic filtering where it helps (createSampler leaves it off on CPU devices).
    imagerySampler_ = gpu::createSampler(device, {.mipmaps = true, .maxAnisotropy = 4.0f});
}

void TerrainLayer::buildPipelines(const render::RenderServices& services) {
    gpu::Device& device = *services.device;
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
    spec.set<int32_t>(shader::kTerrainSpecImageryLayers, int32_t(imageLayerCount()));
    spec.set<int32_t>(shader::kTerrainSpecFirstDrape, int32_t(imageryIndex_.size()));
    surface.specialization = &spec;
    surface.colorFormat = services.colorFormat;
    surface.depthFormat = services.depthFormat;
    surface.name = "terrain surface";
    surface_ = gpu::createGraphicsPipeline(device, surface);

    if (settings_.sky) sky_ = render::createSkyPipeline(device, layout_.vk(), services, "terrain sky");
}

globe::TileHeightRange TerrainLayer::drawnHeights(const globe::TileKey& key) const {
    const double ex = settings_.verticalExaggeration;
    const globe::TileHeightRange r = tiles_->heightRange(key);
    return globe::TileHeightRange{std::min(r.minHeight * ex, 0.0), std::max(r.maxHeight * ex, 0.0)};
}

void TerrainLayer::update(const scene::FrameContext& frame) {
    frame_ = frame.frameNumber + 1;   // 0 means "never used"
    const scene::Camera& camera = *frame.camera;
    tiles_->beginFrame(frame_);
    gpuSlots_->beginFrame(frame_);
    ground_->endFrame();
    stats_ = {};

    globe::SelectorView view;
    view.eye = camera.position();
    view.worldToView = glm::dmat3(camera.viewRotation());
    view.fovYRad = camera.verticalFovRad();
    view.aspect = frame.aspect();
    view.nearPlane = camera.nearPlane();
    view.viewportHeightPx = frame.height;
    syncDrapes(frame.drapes);
    followTime(frame.time);
    const auto& selected = selector_->select(view, [&](const globe::TileKey& k) { return drawnHeights(k); });
    stats_.selection = selector_->stats();

    // Ask for data: elevation and each visible imagery layer, near and coarse first.
    for (const auto& t : selected) {
        tiles_->request(0, t.key, t.distance);
        for (uint32_t i = 0; i < imageLayerCount(); ++i)
            if (imageLayerVisible(i)) tiles_->request(1 + i, t.key, t.distance);
    }
    tiles_->endFrame();

    buildDrawList(frame, selected);
    for (const auto& err : tiles_->errors())
        if (std::find(errors_.begin(), errors_.end(), err) == errors_.end()) errors_.push_back(err);
}

globe::RasterSourceOptions atWmsTime(const globe::RasterSourceOptions& source, const globe::WmsTimeValue& time) {
    globe::RasterSourceOptions o = source;
    // Percent-encoded where a query needs it ('+' of an offset would read as a space).
    std::string value;
    for (char c : time.text) {
        if (c == '+' || c == '&' || c == '#' || c == ' ' || c == '%') {
            char hex[4];
            std::snprintf(hex, sizeof hex, "%%%02X", static_cast<unsigned char>(c));
            value += hex;
        } else {
            value += c;
        }
    }
    o.path += (o.path.find('?') == std::string::npos ? "?" : (o.path.back() == '?' || o.path.back() == '&') ? "" : "&");
    o.path += "TIME=" + value;
    return o;
}

void TerrainLayer::followTime(TimeNs t) {
    for (size_t l = 0; l < imageryIndex_.size(); ++l) {
        const ImageryLayerSettings& layer = settings_.imagery[imageryIndex_[l]];
        if (layer.times.empty()) continue;
        const size_t now = globe::wmsTimeIndexAt(layer.times, t);
        if (now == timeShown_[l]) continue;
        timeShown_[l] = now;   // a value that fails to open is not tried again every frame
        // Opening a WMS reads nothing from the server (a description, in memory): measured
        // 1-3 ms (orbis -vv prints it), so it is done here rather than on a worker.
        const auto t0 = std::chrono::steady_clock::now();
        auto source = globe::RasterSource::open(atWmsTime(layer.source, layer.times[now]));
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (!source) {
            if (std::find(errors_.begin(), errors_.end(), source.message()) == errors_.end()) errors_.push_back(source.message());
            log::error(source.message());
            continue;
        }
        log::debug(layer.name, ": TIME=", layer.times[now].text, " (source opened in ", ms, " ms)");
        tiles_->replaceImagery(uint32_t(1 + l), *source);
    }
}

bool TerrainLayer::imageLayerVisible(uint32_t l) const {
    return l < imageryIndex_.size() ? settings_.imagery[imageryIndex_[l]].visible : drapes_[l - imageryIndex_.size()].visible;
}

double TerrainLayer::imageLayerOpacity(uint32_t l) const {
    return l < imageryIndex_.size() ? settings_.imagery[imageryIndex_[l]].opacity : drapes_[l - imageryIndex_.size()].opacity;
}

void TerrainLayer::syncDrapes(const std::vector<scene::Drape>& drapes) {
    for (DrapeLayer& d : drapes_) d.visible = false;
    bool added = false;
    for (const scene::Drape& drape : drapes) {
        auto it = std::find_if(drapes_.begin(), drapes_.end(), [&](const DrapeLayer& d) { return d.owner == drape.owner; });
        if (it == drapes_.end()) {
            if (imageLayerCount() >= shader::kTerrainMaxImagery) {
                if (!warnedDrapeCap_)
                    log::warn("terrain: at most ", shader::kTerrainMaxImagery, " imagery and draped layers; \"",
                              drape.source->name(), "\" is not drawn on the ground");
                warnedDrapeCap_ = true;
                continue;
            }
            const uint32_t layer = tiles_->addImagery(drape.source);
            drapes_.push_back({drape.owner, drape.version, drape.opacity, true});
            // The drape's content is sharp at every zoom: tiles refine on their grid's error
            // down to its finest level, not only on the ellipsoid's curvature.
            globe::SelectorSettings sel = selector_->settings();
            sel.detailLevel = std::max(sel.detailLevel, tiles_->maxDataLevel(layer));
            selector_->setSettings(sel);
            added = true;
            continue;
        }
        const uint32_t layer = uint32_t(1 + imageryIndex_.size() + size_t(it - drapes_.begin()));
        if (it->version != drape.version) {
            // Its tiles are painted again (only those near what changed, when the layer says
            // where); each shows its old image until its new one is in.
            const auto changed = drape.content ? drape.content->drapeChangedSince(it->version) : std::nullopt;
            if (changed) tiles_->repaintImagery(layer, drape.source, *changed, drape.content->drapeReach());
            else tiles_->replaceImagery(layer, drape.source);
            it->version = drape.version;
        }
        it->opacity = drape.opacity;
        it->visible = true;
    }
    if (added) {
        // The tiles' loads need the worker pool even when the terrain itself reads nothing.
        if (!tiles_->hasPool()) tiles_->setPool(&services_.jobs());
        buildPipelines(services_);
    }
}

std::optional<std::pair<globe::TileKey, uint32_t>> TerrainLayer::residentData(uint32_t layer, const globe::TileKey& tile) {
    const Kind kind = layer == 0 ? Kind::Elevation : Kind::Imagery;
    // The deepest ready ancestor-or-self that is on the GPU or can go there this frame. A
    // drape's empty tile is transparent: its ancestors' coarser painting must not show there.
    const bool drape = layer > imageryIndex_.size();
    std::optional<globe::TileKey> a = tiles_->readyAncestor(layer, tile, drape);
    while (a) {
        const globe::DataKey key{layer, *a};
        const uint32_t generation = tiles_->dataGeneration(layer, *a);
        const bool fits = uploadBytes_ + gpuSlots_->slotBytes(kind) <= settings_.uploadBudgetBytes;
        if (auto slot = gpuSlots_->find(kind, key)) {
            // A repainted tile goes into its slot when the frame's uploads allow; until then
            // the slot's old image is drawn.
            if (gpuSlots_->generation(kind, *slot) != generation && fits) {
                gpuSlots_->setGeneration(kind, *slot, generation);
                uploads_.push_back({kind, *slot, *a, layer});
                uploadBytes_ += gpuSlots_->slotBytes(kind);
            } else if (gpuSlots_->generation(kind, *slot) != generation) {
                deferred_ = true;
            }
            return std::make_pair(*a, *slot);
        }
        if (fits) {
            if (auto slot = gpuSlots_->acquire(kind, key, false, generation)) {
                uploads_.push_back({kind, *slot, *a, layer});
                uploadBytes_ += gpuSlots_->slotBytes(kind);
                return std::make_pair(*a, *slot);
            }
        } else {
            deferred_ = true;
        }
        if (a->level == 0) break;
        a = tiles_->readyAncestor(layer, a->parent(), drape);
    }
    return std::nullopt;
}

std::optional<uint32_t> TerrainLayer::meshSlot(const globe::TileKey& key) {
    const globe::DataKey meshKey{kMeshLayer, key};
    if (auto slot = gpuSlots_->find(Kind::Mesh, meshKey)) return slot;
    // Meshes are never held back: without one, the tile would be a hole.
    auto slot = gpuSlots_->acquire(Kind::Mesh, meshKey, true);
    if (!slot) return std::nullopt;
    uploads_.push_back({Kind::Mesh, *slot, key, kMeshLayer});
    uploadBytes_ += gpuSlots_->slotBytes(Kind::Mesh);
    return slot;
}

void TerrainLayer::buildDrawList(const scene::FrameContext& frame, const std::vector<globe::SelectedTile>& selected) {
    uploads_.clear();
    uploadBytes_ = 0;
    deferred_ = false;
    const size_t count = std::min<size_t>(selected.size(), maxDraws_);
    if (selected.size() > maxDraws_ && !warnedDrawCap_) {
        warnedDrawCap_ = true;
        log::warn("terrain: ", selected.size(), " tiles selected, drawing the first ", maxDraws_,
                  "; raise \"maxScreenSpaceError\"");
    }
    const glm::dmat4 proj = frame.camera->projection(frame.aspect());
    drawItems_.clear();
    drawData_.resize(count * sizeof(shader::TileDraw));
    for (size_t i = 0; i < count; ++i) {
        const globe::TileKey key = selected[i].key;
        const std::optional<uint32_t> mesh = meshSlot(key);
        if (!mesh) continue;
        const shader::TileDraw d = tileDraw(*frame.camera, proj, key);
        const uint32_t drawIndex = uint32_t(drawItems_.size());
        std::memcpy(drawData_.data() + drawIndex * sizeof(d), &d, sizeof(d));
        drawItems_.push_back({*mesh, drawIndex, selected[i].distance});
        stats_.deepestLevel = std::max(stats_.deepestLevel, key.level);
    }
    drawData_.resize(drawItems_.size() * sizeof(shader::TileDraw));
    // Front to back (the selection's distance), so the depth test rejects hidden terrain
    // before it is shaded; vertex buffers are rebound only when the page changes.
    std::stable_sort(drawItems_.begin(), drawItems_.end(),
                     [](const DrawItem& a, const DrawItem& b) { return a.distance < b.distance; });
    stats_.tilesDrawn = drawItems_.size();
    stats_.uploadsThisFrame = uploads_.size();
    stats_.uploadBytesThisFrame = uploadBytes_;
}

shader::TileDraw TerrainLayer::tileDraw(const scene::Camera& camera, const glm::dmat4& proj, const globe::TileKey& key) {
    const globe::GeoExtent e = key.extent();
    const glm::dvec3 center = globe::Ellipsoid::wgs84().toEcef(e.centerLon(), e.centerLat(), 0.0);
    shader::TileDraw d{};
    d.modelViewProj = glm::mat4(proj * camera.modelViewRelativeToEye(center));
    const double cell = key.sizeDeg() * 111320.0 / double(settings_.gridSize - 1);
    const globe::TileHeightRange hr = drawnHeights(key);
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
    if (auto r = residentData(0, key)) {
        d.elevationSlot = int(r->second);
        d.elevationScaleBias = glm::vec4(key.scaleBiasWithin(r->first));
        if (r->first == key) ++stats_.tilesWithOwnElevation;
    }
    d.imagerySlot = glm::ivec4(-1);
    for (uint32_t l = 0; l < imageLayerCount(); ++l) {
        d.imageryScaleBias[l] = glm::vec4(1, 1, 0, 0);
        if (!imageLayerVisible(l)) continue;
        if (auto r = residentData(1 + l, key)) {
            d.imagerySlot[int(l)] = int(r->second);
            d.imageryScaleBias[l] = glm::vec4(key.scaleBiasWithin(r->first));
        }
    }
    return d;
}

void TerrainLayer::writeDescriptors(uint32_t f) {
    if (setVersion_[f] == gpuSlots_->version()) return;
    setVersion_[f] = gpuSlots_->version();
    // Before the first slot of a kind, its image is a dummy.
    gpu::DescriptorWriter(descriptors_.sets[f])
        .storageBuffer(shader::kTerrainBindingDraws, drawBuffers_[f])
        .sampledImage(shader::kTerrainBindingElevation, heightSampler_.vk(), gpuSlots_->elevationView())
        .sampledImage(shader::kTerrainBindingImagery, imagerySampler_.vk(), gpuSlots_->imageryView())
        .update(*services_.device);
}

void TerrainLayer::recordTransfers(const render::RecordContext& rc) {
    VkCommandBuffer cmd = rc.cmd;
    if (!drawData_.empty()) drawBuffers_[rc.slot].write(drawData_.data(), drawData_.size());
    if (!uploads_.empty() || gpuSlots_->growing()) {
        gpuSlots_->beginUploads(cmd);
        for (const PendingUpload& u : uploads_) {
            if (u.kind == Kind::Mesh) {
                const globe::TileMesh mesh = globe::buildTileMesh(u.tile, settings_.gridSize);
                gpuSlots_->uploadMesh(cmd, *rc.uploader, u.slot, mesh.vertices);
            } else if (u.kind == Kind::Elevation) {
                gpuSlots_->uploadElevation(cmd, *rc.uploader, u.slot, *tiles_->elevation(u.tile));
            } else {
                gpuSlots_->uploadImagery(cmd, *rc.uploader, u.slot, *tiles_->imagery(u.layer, u.tile));
            }
        }
        gpuSlots_->endUploads(cmd);
        uploads_.clear();
    }
    writeDescriptors(rc.slot);
}

void TerrainLayer::record(scene::Pass, const render::RecordContext& rc) {
    VkCommandBuffer cmd = rc.cmd;
    const VkDescriptorSet sets[] = {rc.frameSet, descriptors_.sets[rc.slot]};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kFrameSet, 2, sets, 0, nullptr);
    shader::TerrainPush push{};
    push.baseColor = glm::vec3(srgbToLinear(settings_.color.r), srgbToLinear(settings_.color.g), srgbToLinear(settings_.color.b));
    push.verticalExaggeration = float(settings_.verticalExaggeration);
    for (uint32_t l = 0; l < imageLayerCount(); ++l) push.imageryOpacity[int(l)] = float(imageLayerOpacity(l));
    for (uint32_t l = 0; l < imageryIndex_.size(); ++l)
        if (settings_.imagery[imageryIndex_[l]].night) push.nightLayers |= 1u << l;
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
    uint32_t boundPage = UINT32_MAX;
    for (const DrawItem& item : drawItems_) {
        const uint32_t page = gpuSlots_->meshPage(item.meshSlot);
        if (page != boundPage) {
            const VkBuffer vb = gpuSlots_->meshBuffer(item.meshSlot);
            const VkDeviceSize offset = 0;
            vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
            boundPage = page;
        }
        vkCmdDrawIndexed(cmd, indexCount_, 1, 0, gpuSlots_->meshVertexOffset(item.meshSlot), item.drawIndex);
    }
}

uint64_t TerrainLayer::fixedBytes() const {
    uint64_t bytes = indices_.size();
    for (const auto& b : drawBuffers_) bytes += b.size();
    return bytes;
}

uint64_t TerrainLayer::gpuBytes() const { return fixedBytes() + (gpuSlots_ ? gpuSlots_->allocatedBytes() : 0); }

bool TerrainLayer::setParameter(std::string_view name, double value) {
    // The ranges the scene file accepts (create()), so that a saved scene loads again.
    if (name == "maxScreenSpaceError" && kScreenSpaceErrorRange.contains(value)) {
        settings_.maxScreenSpaceError = value;
        if (selector_) {
            globe::SelectorSettings s = selector_->settings();
            s.maxScreenSpaceError = value;
            selector_->setSettings(s);
            selector_->reset();
        }
        return true;
    }
    if (name == "verticalExaggeration" && kExaggerationRange.contains(value)) {
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
    if (const auto i = imageryIndex("imageryOpacity"); i && kImageryOpacityRange.contains(value)) {
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
         .value = settings_.maxScreenSpaceError, .min = kScreenSpaceErrorRange.min, .max = kScreenSpaceErrorRange.max,
         .logarithmic = true},
        {.name = "verticalExaggeration", .label = "Vertical exaggeration", .kind = Kind::Number,
         .value = settings_.verticalExaggeration, .min = kExaggerationRange.min, .max = kExaggerationRange.max,
         .logarithmic = true},
    };
    for (size_t i = 0; i < settings_.imagery.size(); ++i) {
        const ImageryLayerSettings& l = settings_.imagery[i];
        const std::string name = l.name.empty() ? "Imagery " + std::to_string(i + 1) : l.name;
        // In the scene file: "imagery"[i]'s "visible" and "opacity".
        const std::string entry = "/imagery/" + std::to_string(i);
        out.push_back({.name = "imageryVisible" + std::to_string(i), .label = name, .kind = Kind::Toggle,
                       .value = l.visible ? 1.0 : 0.0, .pointer = entry + "/visible"});
        out.push_back({.name = "imageryOpacity" + std::to_string(i), .label = name + " opacity", .kind = Kind::Number,
                       .value = l.opacity, .min = kImageryOpacityRange.min, .max = kImageryOpacityRange.max,
                       .pointer = entry + "/opacity"});
    }
    return out;
}

bool TerrainLayer::busy() const { return (tiles_ && tiles_->loading()) || deferred_; }

std::string TerrainLayer::status() const {
    std::ostringstream s;
    s << "tiles " << stats_.tilesDrawn << " drawn (deepest level " << stats_.deepestLevel << ")";
    if (tiles_) {
        const globe::PagerStats& p = tiles_->stats();
        s << ", " << p.loading << " loading, " << (tiles_->cpuBytes() >> 20) << " MB cached";
        if (p.failed > 0) {
            s << ", " << p.failed << " failed loads (" << p.retried << " tried again)";
            if (!tiles_->errors().empty()) s << "; first: " << tiles_->errors().front();
        }
    }
    s << ", " << (gpuBytes() >> 20) << " MB on the GPU";
    if (!errors_.empty()) s << ", " << errors_.size() << " error(s)";
    return s.str();
}

uint64_t TerrainLayer::cacheBytes() const {
    return (tiles_ ? tiles_->cpuBytes() : 0) + (ground_ ? ground_->cacheBytes() : 0);
}

/// The ground's height as drawn: the DEMs' height times the exaggeration.
static std::optional<double> exaggeratedHeight(const TerrainGround* ground, double exaggeration, double lonDeg, double latDeg) {
    if (!ground) return std::nullopt;
    auto h = ground->heightAt(lonDeg, latDeg);
    if (h) *h *= exaggeration;
    return h;
}

scene::GroundHeightFn TerrainLayer::groundSnapshot() const {
    return [ground = ground_, ex = settings_.verticalExaggeration](double lonDeg, double latDeg) {
        return exaggeratedHeight(ground.get(), ex, lonDeg, latDeg);
    };
}

std::optional<double> TerrainLayer::heightAt(double lonDeg, double latDeg) const {
    return exaggeratedHeight(ground_.get(), settings_.verticalExaggeration, lonDeg, latDeg);
}


}  // namespace orbis::layers
