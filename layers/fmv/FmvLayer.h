#pragma once
// "fmv": full-motion video draped on the terrain from its sensor's pose (MISB ST 0601 KLV).
//
//   {"type": "fmv", "name": "UAV", "path": "flight.ts",
//    "poses": "flight.csv",          -- a pose CSV sidecar, for a video without KLV (or instead of it)
//    "start": "2026-06-21T09:00:00Z", -- UTC of the video's first frame; default: from the KLV
//                                       time stamps, else the pose CSV's first row, else the scene's start
//    "opacity": 0.9, "footprint": true, "frustum": true, "footprintColor": [1, 0.75, 0.1],
//    "heightfield": 129, "distanceMap": 512,
//    "poseOffset": {"heading": 0, "pitch": 0, "roll": 0, "altitude": 0}}   -- a mounting bias
//
// A live stream instead of a file (LiveVideo.h): "url" in place of "path" (udp://, tcp://,
// http://, srt://, rtp://), with "jitter" (seconds of playout delay, 0.1), "noSignal" (seconds of
// silence that count as no signal, 2), "wholeFrames" (the sender puts each frame in one PES:
// a frame interval less latency; false), "damaged" ("show": a frame that lost data on the way
// is shown as the decoder conceals it and counted; "skip": left out with the frames after it up
// to the next key frame), "record" (an MPEG-TS to write the stream into as
// received, to play back later through "path"). A live layer runs on the wall clock, whatever
// the scene's time: the newest frame due, with the pose of its own time; without signal the
// drape goes and the last footprint stays, grey, until the stream comes back by itself.
//
// The pose offsets (degrees, metres) are added to the platform's heading, pitch and roll and to
// the sensor's height before draping (file and live); live-editable, saved with the scene.
//
// The video is opened, indexed and its poses read when the scene loads (clear errors for a
// video without KLV and no "poses", KLV without video, a damaged file); the decoder runs on a
// worker once the layer is shown. Each frame the scene's time picks the video frame (exact:
// the layer is busy until that frame is on the GPU) and the sensor pose (interpolated between
// packets). Around what the sensor sees, a heightfield of the scene's ground (the terrain's
// loaded heights) is sampled on the CPU; on the GPU it is rendered from the sensor into a
// distance map, the footprint's rays are marched over it (compute), and every pixel of the
// scene is projected into the sensor: inside its view and not hidden from it (the distance
// map), it takes the video's colour (compute, then blended over the scene in the FMV pass).
// The footprint's outline and the frustum's edges are drawn as lines.

#include "engine/gpu/Buffer.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/Handle.h"
#include "engine/gpu/Image.h"
#include "engine/gpu/Pipeline.h"
#include "engine/render/RenderContext.h"
#include "engine/scene/Layer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/LayerSetting.h"
#include "engine/scene/SceneDesc.h"
#include "layers/fmv/FmvTimeline.h"
#include "layers/fmv/FramePrefetcher.h"
#include "layers/fmv/LiveVideo.h"
#include "layers/fmv/SensorModel.h"

#include <glm/glm.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace orbis::layers {

/// Added to every pose before draping: a sensor's mounting bias.
struct PoseOffset {
    double headingDeg = 0.0, pitchDeg = 0.0, rollDeg = 0.0, altitude = 0.0;
    bool operator==(const PoseOffset&) const = default;
};
fmv::SensorPose applyOffset(const fmv::SensorPose& pose, const PoseOffset& offset);

struct FmvSettings {
    double opacity = 0.9;
    bool footprint = true, frustum = true;
    glm::dvec3 footprintColor{1.0, 0.75, 0.1};   ///< sRGB
    int heightfieldSize = 129;                   ///< samples a side
    int distanceMapSize = 512;                   ///< pixels a side
    std::optional<double> startUtc;              ///< seconds since 1970 of the video's first frame
    PoseOffset offset;
    std::string name;           ///< the layer's (live: the recordings' names)
    std::string recordFolder;   ///< live: where recordings started from the viewer go (the scene's folder)
};

class FmvLayer final : public scene::Layer,
                       public scene::LiveSettings,
                       public scene::LayerStats,
                       public scene::MovingContent,
                       public scene::LiveFeed {
public:
    /// The scene type: its name, description, factory (create) and the files its object names.
    static scene::LayerType layerType();
    /// The ranges its numeric setting may take, the same for the scene file (create), a live
    /// edit (setParameter) and the panel (liveSettings).
    static constexpr scene::SettingRange kOpacityRange{0.0, 1.0};
    static constexpr scene::SettingRange kHeadingOffsetRange{-180.0, 180.0}, kPitchOffsetRange{-90.0, 90.0},
        kRollOffsetRange{-180.0, 180.0}, kAltitudeOffsetRange{-1000.0, 1000.0};

    static Result<std::unique_ptr<scene::Layer>> create(const scene::LayerDesc& desc, const scene::SceneDesc& scene);
    FmvLayer(std::shared_ptr<fmv::VideoFile> video, fmv::FmvTimeline timeline, FmvSettings settings);
    /// A live stream (already receiving).
    FmvLayer(std::unique_ptr<fmv::LiveVideo> live, FmvSettings settings);
    ~FmvLayer() override;

    std::string_view type() const override { return "fmv"; }
    scene::LiveSettings* asLiveSettings() override { return this; }
    const scene::LayerStats* asStats() const override { return this; }
    const scene::MovingContent* asMovingContent() const override { return this; }
    const scene::LiveFeed* asLiveFeed() const override { return live_ ? this : nullptr; }
    scene::FeedStatus feedStatus() const override;
    Result<std::string> setRecording(bool on) const override;
    void update(const scene::FrameContext& frame) override;
    bool drawsIn(scene::Pass pass) const override { return pass == scene::Pass::Fmv; }
    void recordTransfers(const render::RecordContext& context) override;
    bool computesBefore(scene::Pass pass) const override { return pass == scene::Pass::Fmv && active_; }
    void recordCompute(scene::Pass pass, const render::RecordContext& context) override;
    void record(scene::Pass pass, const render::RecordContext& context) override;
    uint64_t gpuBytes() const override;
    uint64_t itemsDrawn() const override { return active_ ? 1 : 0; }
    bool busy() const override;
    std::string status() const override;
    /// Live: "opacity" (0..1), "footprint" and "frustum" (0/1), "headingOffset", "pitchOffset",
    /// "rollOffset" (degrees), "altitudeOffset" (metres).
    bool setParameter(std::string_view name, double value) override;
    /// The settings above, under the scene file's keys.
    std::vector<scene::LayerSetting> liveSettings() const override;

    // MovingContent: the sensor (its body axes: x the boresight, y image right, z image down),
    // for the camera modes ("pilot" looks through the sensor) and fly-to.
    std::optional<scene::TimeRange> timeRange() const override;
    std::optional<scene::TrackedPose> trackedPose(TimeNs t, const scene::GroundHeightFn& ground) const override;
    std::optional<scene::ContentBounds> contentBounds() const override;

    /// A live stream: its URL, state and counts (as of this frame's update); none for a file.
    bool isLive() const { return live_ != nullptr; }
    const std::string& url() const;
    const fmv::LiveStats& liveStats() const { return liveStats_; }
    /// The live frame shown (or about to be), if any, and its UTC from the KLV time stamps.
    const fmv::VideoFrame* liveFrame() const { return liveFrame_.get(); }
    std::optional<double> liveFrameUtc() const { return liveFrameUtc_; }
    /// Times the footprint was computed (it is again whenever the pose moves).
    uint64_t footprintUpdates() const { return footprintUpdates_; }

    const fmv::FmvTimeline& timeline() const { return timeline_; }
    const FmvSettings& settings() const { return settings_; }
    /// UTC (seconds since 1970) of the video's first frame, as used.
    double videoStartUtc() const { return startUtc_; }
    /// The frame shown (its index), once one is.
    std::optional<size_t> frameShown() const { return shownIndex_; }
    /// The pose used this frame (when active).
    const fmv::SensorPose& pose() const { return pose_; }
    /// The footprint the GPU computed for the last frame shown: ECEF points (4 x kFmvEdgeRays
    /// border points from corner 1 clockwise, then the centre) and whether each met the ground.
    /// Read back after the frame completed.
    std::vector<std::pair<glm::dvec3, bool>> footprint() const;
    /// Times the heightfield was sampled from the ground (stats, tests).
    uint64_t heightfieldBuilds() const { return heightfieldBuilds_; }

private:
    void onPrepare(const render::RenderServices& services) override;
    void createImages(gpu::Device& device);
    void createGrid(const render::RenderServices& services);
    void buildPipelines(const render::RenderServices& services);
    void updateHeightfield(const scene::FrameContext& frame);
    /// The heightfield's samples around origin_ (halfSize_, enu_) from the ground's heights.
    void sampleHeightfield(const std::function<double(double, double)>& groundAt);
    void writeUniforms(const render::RecordContext& rc);
    void writeDescriptors(uint32_t slot);
    void renderDistanceMap(VkCommandBuffer cmd);
    glm::dmat4 sensorClip() const;
    /// Where on screen the video can be this frame: the sensor's frustum between the lowest and
    /// highest ground it sees, projected: its bounding rectangle (x, y, width, height) and its
    /// convex hull as edge equations (none when a part is behind the eye: the whole screen).
    struct ScreenBounds {
        glm::uvec4 rect{0u};
        std::vector<glm::vec3> edges;   // (nx, ny, c): inside when nx x + ny y + c >= 0
    };
    ScreenBounds screenBounds(const scene::FrameContext& frame) const;

    void updateLive(const scene::FrameContext& frame);
    /// The video frame image at the size of the frames (live: made again when it changes).
    void ensureFrameImage(int width, int height);

    std::shared_ptr<fmv::VideoFile> video_;
    fmv::FmvTimeline timeline_;
    std::unique_ptr<fmv::LiveVideo> live_;
    std::shared_ptr<const fmv::VideoFrame> liveFrame_;   // the live frame being uploaded
    fmv::LiveStats liveStats_;
    bool noSignal_ = false;   // live: the stream is silent; the last footprint shows grey
    std::optional<double> liveFrameUtc_;
    uint64_t footprintUpdates_ = 0;
    FmvSettings settings_;
    double startUtc_ = 0.0;
    render::RenderServices services_;
    std::unique_ptr<fmv::FramePrefetcher> frames_;

    // This frame.
    bool active_ = false;          // the scene's time is within the video and a frame is shown
    bool wantedShown_ = false;     // the frame for the scene's time is the one on the GPU
    size_t wantedIndex_ = 0;
    std::optional<size_t> shownIndex_;
    fmv::SensorPose pose_;
    glm::dvec3 eye_{0.0};
    const fmv::VideoFrame* pendingFrame_ = nullptr;   // to upload this frame
    glm::uvec4 rect_{0u};                             // screenBounds().rect this frame

    // The heightfield around what the sensor sees: a square on the tangent plane at origin_.
    glm::dvec3 origin_{0.0};
    glm::dmat3 enu_{1.0};
    double halfSize_ = 0.0, minHeight_ = 0.0, maxHeight_ = 0.0;
    std::vector<float> heights_;          // row 0 north
    std::vector<glm::vec3> gridPositions_;   // relative to origin_
    bool heightfieldDirty_ = false, heightsComplete_ = false;
    uint64_t groundVersion_ = 0, heightfieldBuilds_ = 0;
    glm::dvec3 footprintOrigin_{0.0};   // origin_ when the footprint was computed
    // What the distance map and the footprint were last made from: unchanged (a paused video),
    // they are not made again.
    std::optional<fmv::SensorPose> mapPose_;
    uint64_t mapBuilds_ = 0;

    // GPU objects.
    gpu::Image frameImage_, heightImage_, distanceImage_, distanceDepth_, decalImage_;
    gpu::Buffer gridVertices_, gridIndices_, footprintBuffer_;
    std::vector<gpu::Buffer> uniforms_;
    std::vector<uint64_t> setVersion_;
    uint64_t imagesVersion_ = 1;
    gpu::Image* boundDepth_ = nullptr;
    gpu::Sampler linearSampler_, nearestSampler_;
    gpu::DescriptorSets descriptors_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline drapePipeline_, footprintPipeline_, distancePipeline_, compositePipeline_, outlinePipeline_, frustumPipeline_;
    uint32_t gridIndexCount_ = 0;
    bool gpuReady_ = false, footprintValid_ = false;
};

}  // namespace orbis::layers
