// The scene-file side of the FMV layer: its keys, checked; the video opened and indexed, its
// poses read (KLV, or a pose CSV), and the video's clock placed on the scene's time.
#include "base/Log.h"
#include "engine/scene/JsonReader.h"
#include "globe/Geoid.h"
#include "layers/fmv/FmvLayer.h"
#include "formats/fmv/PoseCsv.h"

#include <algorithm>
#include <memory>

namespace orbis::layers {
namespace {

/// The sensor's poses on the video's clock: from a pose CSV (`csvPath`, its rows' UTC placed by
/// `startUtc`, else the first row is frame 0, which then sets `startUtc`), else the video's KLV.
Result<fmv::FmvTimeline> makeTimeline(const fmv::VideoFile& video, const std::string& csvPath, std::optional<double>& startUtc,
                                      const std::string& where, const std::string& file) {
    const fmv::GeoidHeight geoid = globe::egm96Geoid();
    if (!csvPath.empty()) {
        auto csv = fmv::readPoseCsv(csvPath);
        if (!csv) return makeError(where + "/poses: " + csv.message());
        std::optional<double> start = startUtc;
        std::vector<std::pair<double, fmv::St0601Packet>> placed;
        for (const fmv::PoseSample& row : csv->samples) {
            if (!row.pose.precisionTimeUs) continue;
            const double utc = double(*row.pose.precisionTimeUs) * 1e-6;
            if (!start) start = utc;
            placed.emplace_back(utc - *start, row.pose);
        }
        auto t = fmv::FmvTimeline::fromPackets(placed, csvPath, geoid);
        if (!t) return makeError(where + "/poses: " + t.message());
        if (!startUtc) startUtc = start;
        return std::move(*t);
    }
    if (!video.info().hasKlv)
        return makeError(where + ": " + file +
                         " has no KLV metadata stream: without the sensor's pose the video cannot be placed "
                         "(give \"poses\": a pose CSV sidecar)");
    auto t = fmv::FmvTimeline::fromKlv(video.klv(), file, geoid);
    if (!t) return makeError(where + ": " + t.message());
    return std::move(*t);
}

}  // namespace

Result<std::unique_ptr<scene::Layer>> FmvLayer::create(const scene::LayerDesc& desc, const scene::SceneDesc& scene) {
    scene::JsonReader r(desc.settings, scene.file.string(), desc.jsonPath);
    for (const char* common : {"type", "name", "visible", "viewpoint"}) r.accept(common);
    FmvSettings s;
    const auto path = r.string("path", std::string());
    const auto url = r.string("url", std::string());
    const bool live = url && !url->empty();
    if (r.ok() && (!path || path->empty()) && !live)
        r.fail("path", "name the video file (\"path\") or the live stream (\"url\") to show");
    if (r.ok() && live && path && !path->empty()) r.fail("url", "give a file (\"path\") or a live stream (\"url\"), not both");
    for (const char* fileOnly : {"poses", "start"})
        if (live && desc.settings.contains(fileOnly))
            r.fail(fileOnly, "only for a file (\"path\"): a live stream's poses and times are its KLV's");
    for (const char* liveOnly : {"jitter", "noSignal", "wholeFrames", "damaged", "record"})
        if (!live && desc.settings.contains(liveOnly)) r.fail(liveOnly, "only for a live stream (\"url\")");
    fmv::LiveOptions liveOptions;
    liveOptions.jitterSeconds = r.number("jitter", 0.1, 0.0, 5.0).value_or(0.1);
    liveOptions.noSignalSeconds = r.number("noSignal", 2.0, 0.2, 60.0).value_or(2.0);
    liveOptions.wholeFrames = r.boolean("wholeFrames", false).value_or(false);
    if (const auto damaged = r.string("damaged", std::string("show")); damaged && *damaged != "show" && *damaged != "skip")
        r.fail("damaged", "\"show\" (frames that lost data shown as the decoder conceals them) or \"skip\" (left out up to the next key frame), not \"" + *damaged + "\"");
    else liveOptions.skipDamaged = damaged && *damaged == "skip";
    const auto record = r.string("record", std::string());
    if (const nlohmann::json* offset = r.object("poseOffset")) {
        scene::JsonReader o(*offset, scene.file.string(), desc.jsonPath + "/poseOffset");
        s.offset.headingDeg = o.number("heading", 0.0, kHeadingOffsetRange.min, kHeadingOffsetRange.max).value_or(0.0);
        s.offset.pitchDeg = o.number("pitch", 0.0, kPitchOffsetRange.min, kPitchOffsetRange.max).value_or(0.0);
        s.offset.rollDeg = o.number("roll", 0.0, kRollOffsetRange.min, kRollOffsetRange.max).value_or(0.0);
        s.offset.altitude = o.number("altitude", 0.0, kAltitudeOffsetRange.min, kAltitudeOffsetRange.max).value_or(0.0);
        if (auto done = o.finish(); !done) return done.error();
    }
    const auto poses = r.string("poses", std::string());
    if (auto start = r.string("start", std::string()); start && !start->empty()) {
        auto t = parseIso8601(*start);
        if (!t) r.fail("start", t.message());
        else s.startUtc = toSeconds(*t);
    }
    s.opacity = r.number("opacity", 0.9, kOpacityRange.min, kOpacityRange.max).value_or(0.9);
    s.footprint = r.boolean("footprint", true).value_or(true);
    s.frustum = r.boolean("frustum", true).value_or(true);
    if (auto c = r.numbers("footprintColor", 3, std::vector<double>{1.0, 0.75, 0.1}); c && c->size() == 3) {
        for (double v : *c)
            if (!(v >= 0.0 && v <= 1.0)) r.fail("footprintColor", "each channel is from 0 to 1");
        s.footprintColor = {(*c)[0], (*c)[1], (*c)[2]};
    }
    s.heightfieldSize = int(r.number("heightfield", 129.0, 9.0, 513.0).value_or(129.0));
    s.distanceMapSize = int(r.number("distanceMap", 512.0, 64.0, 4096.0).value_or(512.0));
    if (auto done = r.finish(); !done) return done.error();

    const std::string where = scene.file.string() + ": " + desc.jsonPath;
    s.name = desc.name;
    if (live) {
        s.recordFolder = scene.file.parent_path().string();
        liveOptions.makeGeoid = [] { return fmv::GeoidHeight(globe::egm96Geoid()); };
        if (record && !record->empty()) liveOptions.recordPath = scene.resolve(*record).string();
        auto stream = fmv::LiveVideo::open(*url, std::move(liveOptions));
        if (!stream) return makeError(where + "/url: " + stream.message());
        return std::unique_ptr<scene::Layer>(std::make_unique<FmvLayer>(std::move(*stream), s));
    }
    const std::string file = scene.resolve(*path).string();
    auto video = fmv::VideoFile::open(file);
    if (!video) return makeError(where + ": " + video.message());
    auto timeline = makeTimeline(**video, poses && !poses->empty() ? scene.resolve(*poses).string() : std::string(), s.startUtc,
                                 where, file);
    if (!timeline) return timeline.error();
    // The rotation order against the corners the packets carry (a wrong convention in the
    // producer, or here, shows as corners far off).
    if (const fmv::CornerCheck& c = timeline->cornerCheck(); c.corners > 0) {
        const bool off = c.medianDegrees > std::max(2.0, 0.2 * c.medianFovDegrees);
        if (off)
            log::warn("fmv: ", file, ": the sensor model's corner rays are ", c.medianDegrees, " degrees (median; max ",
                      c.maxDegrees, ") from the corners the packets carry: its rotation order or signs may differ from the producer's");
        else
            log::info("fmv: ", file, ": the sensor model's corner rays are ", c.medianDegrees, " degrees (median; max ",
                      c.maxDegrees, ") from the corners the packets carry");
    }
    if (!s.startUtc) {
        if (timeline->videoStartUtc()) s.startUtc = timeline->videoStartUtc();
        else s.startUtc = toSeconds(scene.time.start);
    }
    return std::unique_ptr<scene::Layer>(
        std::make_unique<FmvLayer>(std::shared_ptr<fmv::VideoFile>(std::move(*video)), std::move(*timeline), s));
}

scene::LayerType FmvLayer::layerType() {
    return {"fmv", "full-motion video (MISB ST 0601 KLV) draped on the terrain from its sensor, from a file or a live stream",
            &FmvLayer::create, {"/path", "/poses", "/record"}};
}

}  // namespace orbis::layers
