// The FMV layer on lavapipe with validation: the synthetic flight (tools/gen/FmvFixture.h) over
// its DEM: draped frames at several times against golden images, the footprint the GPU
// computes against the analytic corners, the ridge hiding the target from the sensor, a sensor
// looking above the horizon, and the clear errors for a video without KLV and KLV without video.
#include "globe/Ellipsoid.h"
#include "layers/fmv/FmvLayer.h"
#include "layers/fmv/SyntheticFlight.h"
#include "layers/fmv/VideoWriter.h"
#include "shared/FmvTypes.h"
#include "tests/render/RenderHelpers.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/GpuTest.h"
#include "tools/gen/FmvFixture.h"
#include "tools/net/UdpRelay.h"
#include "engine/scene/SceneSave.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <set>
#include <thread>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;
using fmv::SyntheticFlight;

fs::path outDir() {
    const auto dir = fs::path(testOutputDir()) / "fmv";
    fs::create_directories(dir);
    return dir;
}

// A fixture per flight start, written once per run (test processes run in parallel: see
// makeFixture): 30 frames at 10 fps, 320 x 240.
const fs::path& fixture(double flightStart) {
    static std::map<double, fs::path> made;
    auto it = made.find(flightStart);
    if (it != made.end()) return it->second;
    const fs::path dir = outDir() / ("flight-" + std::to_string(int(flightStart)));
    const bool ok = makeFixture(dir.string(), [&](const std::string& tmp) {
        fmv::FmvFixtureOptions o;
        o.frames = 30;
        o.width = 320;
        o.height = 240;
        o.flightStart = flightStart;
        o.csv = true;
        auto written = fmv::writeFmvFixture(tmp, o);
        EXPECT_TRUE(written.ok()) << written.message();
        return written.ok();
    });
    EXPECT_TRUE(ok);
    return made.emplace(flightStart, dir).first->second;
}

std::string jsonString(const std::string& s) { return nlohmann::json(s).dump(); }

// UTC text of a time into the flight.
std::string flightTime(double seconds) {
    return formatIso8601(fromSeconds(double(SyntheticFlight::kStartUs) * 1e-6 + seconds), 3);
}

std::string scene(const fs::path& dir, const std::string& viewpoint, const std::string& fmvExtra = "") {
    return R"({"viewpoint": )" + viewpoint + R"(, "time": {"start": ")" + flightTime(-60.0) + R"(", "end": ")" + flightTime(600.0) +
           R"("}, "background": [0.1, 0.1, 0.15], "layers": [)" +
           R"({"type": "terrain", "name": "Ground", "sky": false, "elevation": [)" + jsonString((dir / "flight-dem.tif").string()) +
           R"(]}, {"type": "fmv", "name": "UAV", "path": )" + jsonString((dir / "flight.ts").string()) + fmvExtra + "}]}";
}

const std::string kAbove = R"({"lon": 9.025, "lat": 46.02, "height": 650, "heading": 60, "pitch": -55, "range": 4000})";
const std::string kFromNorth = R"({"lon": 9.035, "lat": 46.02, "height": 650, "heading": 180, "pitch": -40, "range": 4000})";

class FmvRender : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        layers::registerBuiltinLayers(registry_);
    }
    std::unique_ptr<scene::Scene> load(const std::string& json) { return buildScene(json, registry_); }
    ImageRgba8 render(scene::Scene& s, double flightSeconds, uint32_t w = 320, uint32_t h = 240) {
        auto t = parseIso8601(flightTime(flightSeconds));
        EXPECT_TRUE(t.ok());
        s.time().seek(*t);
        return renderSettled(renderer_, device(), s, w, h);
    }
    static layers::FmvLayer& fmvLayer(scene::Scene& s) { return dynamic_cast<layers::FmvLayer&>(*s.resources().back().layer); }

    scene::LayerRegistry registry_;
    std::unique_ptr<render::Renderer> renderer_;
};

// Pixels whose colour differs by more than `tolerance` in any channel.
size_t differing(const ImageRgba8& a, const ImageRgba8& b, int tolerance) {
    return a.pixels.size() == b.pixels.size() ? countDifferentPixels(a, b, tolerance) : size_t(-1);
}

TEST_F(FmvRender, DrapedFramesMatchGoldensAndFollowTheTime) {
    const fs::path& dir = fixture(0.0);
    auto s = load(scene(dir, kAbove));
    ASSERT_TRUE(s);
    auto& layer = fmvLayer(*s);
    EXPECT_NEAR(layer.videoStartUtc(), double(SyntheticFlight::kStartUs) * 1e-6, 1e-3);   // from the KLV
    const auto at05 = render(*s, 0.55);
    ASSERT_TRUE(layer.frameShown());
    EXPECT_EQ(*layer.frameShown(), 5u);   // the frame for 0.55 s: 0.5 s
    EXPECT_TRUE(matchesGolden(at05, "fmv_flight_0.5s"));
    const auto at25 = render(*s, 2.5);
    EXPECT_EQ(*layer.frameShown(), 25u);
    EXPECT_TRUE(matchesGolden(at25, "fmv_flight_2.5s"));
    EXPECT_GT(differing(at05, at25, 8), 300u);   // the platform moved, the frame changed
    // Before the video and after it: nothing draped (the terrain alone).
    const auto before = render(*s, -5.0);   // (the sun moves a little: 1 level of tolerance below)
    EXPECT_FALSE(layer.frameShown() && layer.itemsDrawn());
    const auto after = render(*s, 3.5);
    EXPECT_EQ(differing(before, after, 1), 0u);
    EXPECT_GT(differing(before, at05, 8), 1000u);
    // Opacity 0 leaves the terrain; the outline and frustum off leave nothing.
    ASSERT_TRUE(layer.setParameter("opacity", 0.0));
    ASSERT_TRUE(layer.setParameter("footprint", 0.0));
    ASSERT_TRUE(layer.setParameter("frustum", 0.0));
    EXPECT_EQ(differing(render(*s, 0.55), before, 1), 0u);
}

TEST_F(FmvRender, FootprintCornersLandWithinADemCellOfTheAnalyticOnes) {
    const fs::path& dir = fixture(0.0);
    auto s = load(scene(dir, kAbove));
    ASSERT_TRUE(s);
    auto& layer = fmvLayer(*s);
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    const double cell = 6371000.0 * glm::radians(1.0 / 7200.0) * std::cos(glm::radians(46.02));   // 10.7 m east-west
    double worst = 0.0;
    for (double t : {0.0, 1.0, 2.9}) {
        render(*s, t);
        const auto points = layer.footprint();
        ASSERT_EQ(points.size(), size_t(shader::kFmvFootprintRays));
        // The analytic corners: the frame's pose against the analytic terrain (the packet's corners).
        const fmv::St0601Packet packet = SyntheticFlight::packet(std::floor(t * 10.0 + 1e-9) / 10.0);
        for (int i = 0; i < 4; ++i) {
            const auto [got, hit] = points[size_t(i) * shader::kFmvEdgeRays];
            EXPECT_TRUE(hit);
            const fmv::LatLonDeg c = *packet.corner(i);
            const glm::dvec3 want = wgs84.toEcef(c.lonDeg, c.latDeg, SyntheticFlight::height(c.lonDeg, c.latDeg));
            worst = std::max(worst, glm::length(got - want));
            EXPECT_LT(glm::length(got - want), cell) << "t = " << t << ", corner " << i + 1;
        }
        const glm::dvec3 target = wgs84.toEcef(SyntheticFlight::kTargetLon, SyntheticFlight::kTargetLat,
                                               SyntheticFlight::height(SyntheticFlight::kTargetLon, SyntheticFlight::kTargetLat));
        EXPECT_LT(glm::length(points.back().first - target), cell) << "centre, t = " << t;
    }
    std::printf("[ footprint ] worst corner error against the analytic corners: %.2f m (DEM cell %.1f m)\n", worst, cell);
}

TEST_F(FmvRender, TheRidgeHidesTheTargetFromTheSensor) {
    // 120 s into the flight the platform is east of the target, and the ridge between them
    // hides it: every ray of the view ends on the ridge's east face. The target's pixel shows
    // the terrain, not the video; where the centre ray meets the ridge shows the video.
    const fs::path& dir = fixture(120.0);
    auto s = load(scene(dir, kFromNorth));
    ASSERT_TRUE(s);
    auto& layer = fmvLayer(*s);
    const auto draped = render(*s, 121.0);
    ASSERT_TRUE(layer.frameShown());
    EXPECT_TRUE(matchesGolden(draped, "fmv_ridge_occlusion"));
    ASSERT_TRUE(layer.setParameter("footprint", 0.0));
    ASSERT_TRUE(layer.setParameter("frustum", 0.0));
    const auto video = render(*s, 121.0);
    ASSERT_TRUE(layer.setParameter("opacity", 0.0));
    const auto ground = render(*s, 121.0);
    // Where the target and a point on the near slope (sensor side) are on screen.
    const auto project = [&](double lon, double lat) {
        const glm::dvec3 p = globe::Ellipsoid::wgs84().toEcef(lon, lat, SyntheticFlight::height(lon, lat));
        const scene::Camera& cam = s->camera();
        const glm::dvec4 clip = cam.projection(320.0 / 240.0) * cam.viewRotation() * glm::dvec4(p - cam.position(), 1.0);
        return glm::ivec2(int((clip.x / clip.w * 0.5 + 0.5) * 320.0), int((clip.y / clip.w * 0.5 + 0.5) * 240.0));
    };
    const auto pixelDiffers = [&](glm::ivec2 px) {
        int most = 0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                for (int c = 0; c < 3; ++c) {
                    const size_t i = (size_t(px.y + dy) * 320 + size_t(px.x + dx)) * 4 + size_t(c);
                    most = std::max(most, std::abs(int(video.pixels[i]) - int(ground.pixels[i])));
                }
        return most > 10;
    };
    const double mPerLon = 111320.0 * std::cos(glm::radians(SyntheticFlight::kTargetLat));
    const fmv::TerrainHeights terrain = SyntheticFlight::terrain();
    const fmv::SensorCamera sensor(SyntheticFlight::pose(121.0));
    const fmv::GroundHit centreHit = fmv::intersectGround(sensor.position(), sensor.ray(0.0, 0.0), &terrain, 1.0);
    const globe::Geodetic onRidge = globe::Ellipsoid::wgs84().toGeodetic(centreHit.ecef);
    EXPECT_NEAR((onRidge.lonDeg - SyntheticFlight::kTargetLon) * mPerLon, 950.0, 100.0);   // the analytic ray: on the ridge
    const glm::ivec2 target = project(SyntheticFlight::kTargetLon, SyntheticFlight::kTargetLat);
    const glm::ivec2 ridge = project(onRidge.lonDeg, onRidge.latDeg);
    ASSERT_TRUE(target.x > 1 && target.x < 318 && target.y > 1 && target.y < 238) << target.x << " " << target.y;
    ASSERT_TRUE(ridge.x > 1 && ridge.x < 318 && ridge.y > 1 && ridge.y < 238) << ridge.x << " " << ridge.y;
    EXPECT_FALSE(pixelDiffers(target)) << "the target is draped though the ridge hides it";
    EXPECT_TRUE(pixelDiffers(ridge)) << "the ridge's face the sensor sees is not draped";
    // The footprint's centre ray (GPU) stops on the ridge too, not at the target.
    const auto points = layer.footprint();
    EXPECT_LT(glm::length(points.back().first - centreHit.ecef), 30.0);
}

TEST_F(FmvRender, ASensorLookingAboveTheHorizonStaysFinite) {
    // Poses from a CSV: the sensor tilted up 10 degrees (its upper corners see the sky).
    const fs::path& dir = fixture(0.0);
    const fs::path csv = outDir() / "above-horizon.csv";
    {
        std::ofstream out(csv);
        out << "time_us,sensor_lat,sensor_lon,sensor_hae,platform_heading,sensor_rel_az,sensor_rel_el,hfov,vfov\n";
        for (int i = 0; i < 31; ++i)
            out << SyntheticFlight::kStartUs + uint64_t(i) * 100000 << ",46.02,9.0,1500,90,0," << (i % 2 ? 10 : 8) << ",60,40\n";
    }
    auto s = load(scene(dir, kAbove, R"(, "poses": )" + jsonString(csv.string())));
    ASSERT_TRUE(s);
    auto& layer = fmvLayer(*s);
    const auto img = render(*s, 1.0);
    const auto points = layer.footprint();
    ASSERT_EQ(points.size(), size_t(shader::kFmvFootprintRays));
    size_t clamped = 0;
    for (const auto& [p, hit] : points) {
        ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
        const globe::Geodetic g = globe::Ellipsoid::wgs84().toGeodetic(p);
        EXPECT_GT(g.height, -10.0);   // on the ground (the ellipsoid beyond the DEM) or the horizon, not in space
        EXPECT_LT(g.height, 1200.0);
        clamped += hit ? 0 : 1;
    }
    EXPECT_GT(clamped, 10u);                                 // the upper edge sees the horizon
    EXPECT_FALSE(points[2 * shader::kFmvEdgeRays].second == false);   // corner 3 (lower right) meets the ground
    EXPECT_FALSE(img.pixels.empty());
}

TEST_F(FmvRender, BadVideosGiveClearErrors) {
    const fs::path dir = outDir() / "bad";
    fs::create_directories(dir);
    // A video without KLV and no poses.
    fmv::FmvFixtureOptions o;
    o.frames = 3;
    o.width = 64;
    o.height = 48;
    o.klv = false;
    ASSERT_TRUE(fmv::writeFmvFixture(dir, o).ok());
    auto parsed = scene::parseSceneText(scene(dir, kAbove), "bad.json", dir);
    ASSERT_TRUE(parsed.ok()) << parsed.message();
    auto built = scene::Scene::build(std::move(*parsed), registry_);
    ASSERT_FALSE(built.ok());
    EXPECT_NE(built.message().find("has no KLV metadata stream"), std::string::npos) << built.message();
    // KLV without video.
    fmv::VideoWriteOptions k;
    k.withVideo = false;
    const fs::path klvOnly = dir / "klv-only.ts";
    {
        auto w = fmv::VideoWriter::create(klvOnly.string(), k);
        ASSERT_TRUE(w.ok()) << w.message();
        ASSERT_TRUE((*w)->writeKlv(0.0, std::vector<uint8_t>(30, 1)).ok());
        ASSERT_TRUE((*w)->close().ok());
    }
    std::string text = scene(dir, kAbove);
    const std::string ts = jsonString((dir / "flight.ts").string());
    text.replace(text.find(ts), ts.size(), jsonString(klvOnly.string()));
    parsed = scene::parseSceneText(text, "bad.json", dir);
    ASSERT_TRUE(parsed.ok()) << parsed.message();
    built = scene::Scene::build(std::move(*parsed), registry_);
    ASSERT_FALSE(built.ok());
    EXPECT_NE(built.message().find("KLV metadata but no video stream"), std::string::npos) << built.message();
    // A poses file that is not there; an opacity out of range.
    parsed = scene::parseSceneText(scene(dir, kAbove, R"(, "poses": "nowhere.csv")"), "bad.json", dir);
    ASSERT_TRUE(parsed.ok()) << parsed.message();
    built = scene::Scene::build(std::move(*parsed), registry_);
    ASSERT_FALSE(built.ok());
    EXPECT_NE(built.message().find("nowhere.csv"), std::string::npos) << built.message();
    parsed = scene::parseSceneText(scene(dir, kAbove, R"(, "opacity": 2)"), "bad.json", dir);
    ASSERT_TRUE(parsed.ok()) << parsed.message();
    built = scene::Scene::build(std::move(*parsed), registry_);
    ASSERT_FALSE(built.ok());
    EXPECT_NE(built.message().find("opacity"), std::string::npos) << built.message();
}

// A live feed: the flight's first 26 frames (320 x 240, as the file fixture) sent over UDP in real
// time while the scene renders; then the sender stops.
std::string liveScene(int port, const std::string& viewpoint) {
    return R"({"viewpoint": )" + viewpoint + R"(, "time": {"start": ")" + flightTime(-60.0) + R"(", "end": ")" + flightTime(600.0) +
           R"("}, "background": [0.1, 0.1, 0.15], "layers": [)" +
           R"({"type": "terrain", "name": "Ground", "sky": false, "elevation": [)" + jsonString((fixture(0.0) / "flight-dem.tif").string()) +
           R"(]}, {"type": "fmv", "name": "UAV", "url": "udp://127.0.0.1:)" + std::to_string(port) +
           R"(", "wholeFrames": true, "noSignal": 1.0, "jitter": 0.05}]})";
}

TEST_F(FmvRender, ALiveFeedDrapesLikeTheFileAndGreysWithoutSignal) {
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    auto s = load(liveScene(port, kAbove));
    ASSERT_TRUE(s);
    auto& layer = fmvLayer(*s);
    ASSERT_TRUE(layer.isLive());
    // The terrain alone first (nothing received: waited for until there is no signal).
    const auto ground = renderSettled(renderer_, device(), *s, 320, 240);
    EXPECT_NE(layer.status().find("no signal"), std::string::npos) << layer.status();
    EXPECT_FALSE(layer.busy());
    std::atomic<bool> stop{false};
    fmv::FmvStreamOptions o;
    o.frames = 26;
    o.width = 320;
    o.height = 240;
    auto sent = std::async(std::launch::async, [&] { return fmv::streamFmvFixture("udp://127.0.0.1:" + std::to_string(port), o, stop); });
    // Frames are draped as they come, at whatever the scene's time is.
    std::set<int> shown;
    while (sent.wait_for(std::chrono::milliseconds(0)) != std::future_status::ready) {
        renderOnce(*renderer_, *s);
        if (const fmv::VideoFrame* f = layer.liveFrame()) shown.insert(fmv::fixtureFrameNumber(f->rgba, f->width, f->height));
    }
    auto result = sent.get();
    ASSERT_TRUE(result.ok()) << result.message();
    // The last frame (25, 2.5 s into the flight) stays; the scene's time is not the flight's.
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(400);
    while (std::chrono::steady_clock::now() < until) renderOnce(*renderer_, *s);
    const auto live = renderSettled(renderer_, device(), *s, 320, 240);
    ASSERT_TRUE(layer.liveFrame());
    EXPECT_EQ(fmv::fixtureFrameNumber(layer.liveFrame()->rgba, 320, 240), 25);
    EXPECT_GE(shown.size(), 3u) << "frames draped while the stream ran";
    EXPECT_NE(layer.status().find("live 320x240"), std::string::npos) << layer.status();
    // Against the file-driven render of the same frame: the geometry is the same; the pictures
    // could differ by the live encoder's coding (zerolatency: no look-ahead); measured: no pixel
    // off by more than 24 levels; allowed: 1 %.
    auto fileScene = load(scene(fixture(0.0), kAbove));
    const auto file = render(*fileScene, 2.5);
    const size_t off = differing(live, file, 24);
    std::printf("[ live ] %zu of %d pixels differ from the file's frame 25 by more than 24 levels\n", off, 320 * 240);
    EXPECT_LT(off, size_t(320 * 240 / 100));
    EXPECT_GT(differing(live, ground, 24), 1000u);
    // Silence: no signal; the drape goes, the footprint stays grey.
    const auto silent = std::chrono::steady_clock::now() + std::chrono::seconds(4);
    while (std::chrono::steady_clock::now() < silent && layer.liveStats().state != fmv::LiveState::NoSignal) renderOnce(*renderer_, *s);
    ASSERT_EQ(layer.liveStats().state, fmv::LiveState::NoSignal);
    EXPECT_NE(layer.status().find("no signal"), std::string::npos) << layer.status();
    const auto grey = renderSettled(renderer_, device(), *s, 320, 240);
    EXPECT_TRUE(matchesGolden(grey, "fmv_live_no_signal"));
    const size_t outline = differing(grey, ground, 8);
    EXPECT_GT(outline, 50u) << "the footprint and frustum are drawn";
    EXPECT_LT(outline, 3000u) << "only lines: the video is not draped";
}

TEST_F(FmvRender, PoseOffsetsMoveTheFootprintAndAreSavedWithTheScene) {
    const fs::path& dir = fixture(0.0);
    auto s = load(scene(dir, kAbove, R"(, "poseOffset": {"heading": 2})"));
    ASSERT_TRUE(s);
    auto& layer = fmvLayer(*s);
    EXPECT_EQ(layer.settings().offset.headingDeg, 2.0);
    render(*s, 1.0);
    const auto biased = layer.footprint();
    ASSERT_TRUE(layer.setParameter("headingOffset", 0.0));
    render(*s, 1.0);
    const auto plain = layer.footprint();
    ASSERT_EQ(biased.size(), plain.size());
    // 2 degrees of heading about a sensor 2.5 km from the target: the centre moves ~90 m.
    const double moved = glm::length(biased.back().first - plain.back().first);
    EXPECT_GT(moved, 50.0);
    EXPECT_LT(moved, 150.0);
    EXPECT_FALSE(layer.setParameter("pitchOffset", 120.0));   // outside -90..90
    ASSERT_TRUE(layer.setParameter("altitudeOffset", -25.0));
    ASSERT_TRUE(layer.setParameter("rollOffset", 1.5));
    render(*s, 1.0);
    EXPECT_NEAR(layer.pose().height, SyntheticFlight::pose(1.0).height - 25.0, 0.5);
    const nlohmann::json saved = scene::sceneToJson(*s, outDir() / "offsets.json");
    const nlohmann::json& fmv = saved["layers"][1];
    EXPECT_EQ(fmv["poseOffset"]["heading"], 0.0);
    EXPECT_EQ(fmv["poseOffset"]["altitude"], -25.0);
    EXPECT_EQ(fmv["poseOffset"]["roll"], 1.5);
    // Bad offsets and keys of the other kind of source are clear errors.
    for (const auto& [extra, words] : std::vector<std::pair<std::string, std::string>>{
             {R"(, "poseOffset": {"pitch": 95})", "pitch"},
             {R"(, "poseOffset": {"yaw": 1})", "yaw"},
             {R"(, "record": "x.ts")", "only for a live stream"},
             {R"(, "url": "udp://127.0.0.1:9")", "not both"}}) {
        auto parsed = scene::parseSceneText(scene(dir, kAbove, extra), "bad.json", dir);
        ASSERT_TRUE(parsed.ok()) << parsed.message();
        auto built = scene::Scene::build(std::move(*parsed), registry_);
        ASSERT_FALSE(built.ok()) << extra;
        EXPECT_NE(built.message().find(words), std::string::npos) << built.message();
    }
    auto parsed = scene::parseSceneText(liveScene(9, kAbove).replace(liveScene(9, kAbove).find("udp://"), 6, "nosuch://"), "bad.json", dir);
    ASSERT_TRUE(parsed.ok()) << parsed.message();
    auto built = scene::Scene::build(std::move(*parsed), registry_);
    ASSERT_FALSE(built.ok());
    EXPECT_NE(built.message().find("cannot receive nosuch://"), std::string::npos) << built.message();
    const std::string live = liveScene(9, kAbove);
    const std::string damaged = std::string(live).replace(live.find("\"wholeFrames\""), 0, "\"damaged\": \"sometimes\", ");
    parsed = scene::parseSceneText(damaged, "bad.json", dir);
    ASSERT_TRUE(parsed.ok()) << parsed.message();
    built = scene::Scene::build(std::move(*parsed), registry_);
    ASSERT_FALSE(built.ok());
    EXPECT_NE(built.message().find("\"skip\""), std::string::npos) << built.message();
    EXPECT_NE(built.message().find("sometimes"), std::string::npos) << built.message();
}

}  // namespace
}  // namespace orbis::test
