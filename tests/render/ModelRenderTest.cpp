// The model layer on lavapipe with validation: glTF models (the real sample files and the
// repository's wagon), the heading convention on the globe, the train scene on its trajectory
// at several times, the camera modes, and one time reached through different seek paths giving
// the same picture (trajectory, models and FMV together).
#include "engine/scene/CameraRig.h"
#include "globe/Ellipsoid.h"
#include "formats/livefeed/NmeaWriter.h"
#include "layers/models/ModelLayer.h"
#include "tests/livefeed/FeedServer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/GpuTest.h"

#include <cpl_vsi.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = ORBIS_SOURCE_DIR;
const fs::path kShared = fs::path(ORBIS_SOURCE_DIR) / ".." / "shared" / "data";

std::string jsonString(const fs::path& p) { return nlohmann::json(p.string()).dump(); }

// The train scene (assets/scenes/train.json) with absolute paths, a camera mode and optionally
// the FMV showcase's video over the same valley and time.
std::string trainScene(const std::string& camera, bool withFmv = false) {
    const fs::path assets = kSource / "assets";
    std::string layers = R"({"type": "terrain", "name": "Ground", "sky": false, "elevation": [)" +
                         jsonString(assets / "generated/fmv/flight-dem.tif") + "]}";
    if (withFmv) layers += R"(, {"type": "fmv", "name": "UAV", "path": )" + jsonString(assets / "generated/fmv/flight.ts") + "}";
    layers += R"(, {"type": "model", "name": "Train", "file": )" + jsonString(assets / "models/wagon.gltf") +
              R"(, "trajectory": {"file": )" + jsonString(assets / "scenes/train-track.csv") +
              R"(, "start": "2026-06-21T09:00:00Z"}, "copies": {"count": 5, "spacing": 0.95},
                  "path": {"show": true}, "label": true})";
    return R"({"viewpoint": {"lon": 9.03, "lat": 46.012, "height": 600, "heading": 0, "pitch": -35, "range": 3500},
               "background": [0.05, 0.06, 0.1], "camera": )" + camera + R"(, "layers": [)" + layers + "]}";
}

TimeNs trainTime(double seconds) { return parseIso8601("2026-06-21T09:00:00Z").value() + fromSeconds(seconds); }

class ModelRender : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        layers::registerBuiltinLayers(registry_);
    }
    std::unique_ptr<scene::Scene> load(const std::string& json) { return buildScene(json, registry_); }
    ImageRgba8 render(scene::Scene& s, uint32_t w = 320, uint32_t h = 200) {
        return renderSettled(renderer_, device(), s, w, h);
    }
    static layers::ModelLayer& model(scene::Scene& s) {
        return dynamic_cast<layers::ModelLayer&>(*s.find("Train")->layer);
    }

    scene::LayerRegistry registry_;
    std::unique_ptr<render::Renderer> renderer_;
};

TEST_F(ModelRender, TexturedBoxFromTheSampleModels) {
    const fs::path box = kShared / "models" / "BoxTextured.glb";
    if (!fs::exists(box)) GTEST_SKIP() << "shared data absent: " << box;
    auto s = load(R"({"viewpoint": {"lon": 7.0, "lat": 46.0, "height": 0, "heading": 30, "pitch": -25, "range": 6},
        "time": {"start": "2026-03-20T10:00:00Z"},
        "layers": [{"type": "globe", "name": "Earth"},
                   {"type": "model", "name": "Box", "file": )" + jsonString(box) +
                  R"(, "position": [7.0, 46.0, 0.5], "label": true}]})");
    ASSERT_TRUE(s);
    EXPECT_TRUE(matchesGolden(render(*s), "model_box_textured"));
}

TEST_F(ModelRender, OpacityBlendsTheModelOverTheScene) {
    // The wagon over the globe at half opacity: where it covers the globe, each pixel lies
    // between the globe alone and the opaque wagon (its depth is drawn first, so the faces
    // behind the front ones add nothing), and opacity 0 is the globe alone. The pipelines for
    // it are made only when the opacity first drops below 1.
    auto s = load(R"({"viewpoint": {"lon": 7.0, "lat": 46.0, "height": 0, "heading": 30, "pitch": -25, "range": 40},
        "time": {"start": "2026-03-20T10:00:00Z"},
        "layers": [{"type": "globe", "name": "Earth"},
                   {"type": "model", "name": "Train", "file": )" + jsonString(kSource / "assets/models/wagon.gltf") +
                  R"(, "position": [7.0, 46.0, 2]}]})");
    ASSERT_TRUE(s);
    const auto opaque = render(*s);
    s->find("Train")->visible = false;
    const auto globeOnly = render(*s);
    s->find("Train")->visible = true;
    ASSERT_TRUE(model(*s).setParameter("opacity", 0.5));
    const auto half = render(*s);
    size_t covered = 0, between = 0, changed = 0;
    for (size_t i = 0; i < half.pixels.size(); i += 4) {
        int diff = 0;
        for (size_t c = 0; c < 3; ++c) diff = std::max(diff, std::abs(int(opaque.pixels[i + c]) - int(globeOnly.pixels[i + c])));
        if (diff < 30) continue;
        ++covered;
        bool in = true;
        for (size_t c = 0; c < 3; ++c) {
            const int lo = std::min(opaque.pixels[i + c], globeOnly.pixels[i + c]), hi = std::max(opaque.pixels[i + c], globeOnly.pixels[i + c]);
            in = in && half.pixels[i + c] + 3 >= lo && half.pixels[i + c] <= hi + 3;
        }
        between += in ? 1 : 0;
        changed += std::abs(int(half.pixels[i]) - int(opaque.pixels[i])) > 2 ? 1 : 0;
    }
    ASSERT_GT(covered, size_t(500)) << "the wagon should cover part of the view";
    EXPECT_GT(between, covered * 95 / 100);
    EXPECT_GT(changed, covered * 9 / 10) << "half opacity should differ from the opaque wagon";
    ASSERT_TRUE(model(*s).setParameter("opacity", 0.0));
    EXPECT_LT(countDifferentPixels(render(*s), globeOnly, 1), size_t(10));
    EXPECT_FALSE(model(*s).setParameter("opacity", -0.1));
}

TEST_F(ModelRender, HeadingNinetyPointsEast) {
    // The wagon's front (glTF +Z) along the local east at heading 90, north at 0; its roof up.
    for (double heading : {0.0, 90.0}) {
        auto s = load(R"({"time": {"start": "2026-03-20T10:00:00Z"}, "layers": [{"type": "model", "name": "Train", "file": )" +
                      jsonString(kSource / "assets/models/wagon.gltf") + R"(, "position": [179.99, -60.0, 100], "attitude": [)" +
                      std::to_string(heading) + R"(, 0, 0]}]})");
        ASSERT_TRUE(s);
        render(*s, 64, 64);
        const auto& transforms = model(*s).copyTransforms();
        ASSERT_EQ(transforms.size(), 1u);
        const glm::dmat3 enu = globe::Ellipsoid::wgs84().enuFrame(179.99, -60.0);
        const glm::dvec3 front = glm::normalize(glm::dmat3(transforms[0]) * glm::dvec3(0, 0, 1));
        const glm::dvec3 up = glm::normalize(glm::dmat3(transforms[0]) * glm::dvec3(0, 1, 0));
        const glm::dvec3 expected = heading == 90.0 ? enu[0] : enu[1];
        EXPECT_NEAR(glm::dot(front, expected), 1.0, 1e-12) << "heading " << heading;
        EXPECT_NEAR(glm::dot(up, enu[2]), 1.0, 1e-12);
        const glm::dvec3 place = globe::Ellipsoid::wgs84().toEcef(179.99, -60.0, 100.0);
        EXPECT_LT(glm::length(glm::dvec3(transforms[0][3]) - place), 1e-6);
    }
}

TEST_F(ModelRender, TrainAlongItsTrackAtSeveralTimes) {
    auto s = load(trainScene(R"({"mode": "follow", "target": "Train", "distance": 70, "heading": 150, "pitch": -20})"));
    ASSERT_TRUE(s);
    // No "time" in the scene: the range is the trajectory's (plus the copies' lag).
    EXPECT_EQ(s->time().start(), trainTime(0.0));
    EXPECT_EQ(s->time().end(), trainTime(100.0 + 4 * 0.95));
    for (double t : {20.0, 60.0, 95.0}) {
        s->time().seek(trainTime(t));
        const auto image = render(*s);
        EXPECT_TRUE(matchesGolden(image, "model_train_" + std::to_string(int(t)) + "s"));
        EXPECT_EQ(model(*s).itemsDrawn(), 5u) << "every wagon in view at " << t << " s";
    }
}

TEST_F(ModelRender, CameraModes) {
    for (const char* mode : {"overview", "pilot", "above", "aside", "below"}) {
        const std::string camera = std::string(R"({"mode": ")") + mode + R"(", "target": "Train", "eye": [0, 0, -2.5]})";
        auto s = load(trainScene(camera));
        ASSERT_TRUE(s);
        s->time().seek(trainTime(60.0));
        const auto image = render(*s);
        EXPECT_TRUE(matchesGolden(image, std::string("model_camera_") + mode)) << mode;
        // The camera is where the mode puts it at this time.
        const auto pose = s->cameraModePose(320.0 / 200.0);
        ASSERT_TRUE(pose) << mode;
        EXPECT_LT(glm::length(pose->position - s->camera().position()), 1.0) << mode;
    }
}

TEST_F(ModelRender, SameTimeThroughDifferentSeekPathsGivesTheSameImage) {
    const fs::path video = kSource / "assets/generated/fmv/flight.ts";
    ASSERT_TRUE(fs::exists(video)) << "the build generates " << video;
    const std::string json = trainScene(R"({"mode": "overview", "target": "Train"})", true);
    // Path A: straight to 12 s.
    auto a = load(json);
    ASSERT_TRUE(a);
    a->time().seek(trainTime(12.0));
    const auto direct = render(*a);
    // Path B: to 25 s, played backwards and forwards in uneven steps, then a seek to 12 s.
    auto b = load(json);
    ASSERT_TRUE(b);
    b->time().seek(trainTime(25.0));
    render(*b);
    b->time().setRate(-3.0);
    b->time().play();
    for (double wall : {0.37, 1.1, 0.05}) {
        b->time().advance(wall);
        renderer_->render(*b, false);
    }
    b->time().pause();
    b->time().seek(trainTime(2.0));
    render(*b);
    b->time().seek(trainTime(12.0));
    const auto viaSeeks = render(*b);
    EXPECT_EQ(b->time().now(), a->time().now());
    EXPECT_EQ(countDifferentPixels(direct, viaSeeks, 0), 0u);
    if (HasFailure()) {
        (void)writePng(testOutputDir() + "/model_seek_direct.png", direct);
        (void)writePng(testOutputDir() + "/model_seek_via.png", viaSeeks);
    }
    EXPECT_TRUE(matchesGolden(direct, "model_train_fmv_12s"));
}

// Models in mesh formats (Assimp) from Debian's assimp-testmodels, side by side on the globe at
// true scale and upright: the COLLADA duck with its TGA texture, the Wuson figure as PLY, the
// 3DS rock (Z up in its file) and the spider as OBJ with its Windows texture paths, scaled down.
TEST_F(ModelRender, MeshFormatsStandUprightAtTrueScale) {
    const fs::path models = "/usr/share/assimp/models";
    if (!fs::exists(models / "Collada" / "duck.dae")) GTEST_SKIP() << "assimp-testmodels is not installed";
    const auto at = [](double east) { return std::string("[").append(std::to_string(7.0 + east / 77000.0)).append(", 46.0, 0.0]"); };
    auto s = load(R"({"viewpoint": {"lon": 7.0000325, "lat": 46.0, "height": 0, "heading": 0, "pitch": -12, "range": 14},
        "time": {"start": "2026-03-20T10:00:00Z"},
        "layers": [{"type": "globe", "name": "Earth"},
                   {"type": "model", "name": "Duck", "file": )" + jsonString(models / "Collada" / "duck.dae") + R"(, "position": )" + at(0.0) + R"(, "attitude": [200, 0, 0]},
                   {"type": "model", "name": "Wuson", "file": )" + jsonString(models / "PLY" / "Wuson.ply") + R"(, "position": )" + at(2.5) + R"(, "attitude": [180, 0, 0]},
                   {"type": "model", "name": "Rock", "file": )" + jsonString(models / "3DS" / "fels.3ds") + R"(, "position": )" + at(5.5) + R"(, "scale": 0.5},
                   {"type": "model", "name": "Spider", "file": )" + jsonString(models / "OBJ" / "spider.obj") + R"(, "position": )" + at(-3.0) + R"(, "scale": 0.015, "attitude": [180, 0, 0]}]})");
    ASSERT_TRUE(s);
    EXPECT_TRUE(matchesGolden(render(*s, 400, 240), "model_mesh_formats"));
    // glTF-only settings refused for glTF; the mesh settings checked.
    const fs::path wagon = kSource / "assets/models/wagon.gltf";
    auto desc = scene::parseSceneText(R"({"layers": [{"type": "model", "name": "M", "file": )" + jsonString(wagon) + R"(, "position": [0, 0, 0], "up": "z"}]})", "t.json", ".");
    ASSERT_TRUE(desc);
    auto refused = scene::Scene::build(std::move(*desc), registry_);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("for mesh formats"), std::string::npos) << refused.message();
    auto sideways = scene::parseSceneText(R"({"layers": [{"type": "model", "name": "M", "file": )" + jsonString(models / "PLY" / "Wuson.ply") + R"(, "position": [0, 0, 0], "up": "x"}]})", "t.json", ".");
    ASSERT_TRUE(sideways);
    auto bad = scene::Scene::build(std::move(*sideways), registry_);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find("\"y\" or \"z\""), std::string::npos) << bad.message();
}

// The other mesh formats side by side the same way: the Wuson figure as binary STL (no shared
// vertices: Assimp joins them), the spider as FBX (centimetres, its texture on the author's
// disk: drawn white, with a warning) and the COLLADA duck inside a KMZ, as SketchUp writes them.
TEST_F(ModelRender, StlFbxAndKmzModelsStandUprightAtTrueScale) {
    const fs::path models = "/usr/share/assimp/models";
    if (!fs::exists(models / "Collada" / "duck.dae")) GTEST_SKIP() << "assimp-testmodels is not installed";
    const fs::path dir = fs::path(testOutputDir()) / ("model-kmz-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path kmz = dir / "duck.kmz";
    const auto slurp = [](const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::string>>{
             {"doc.kml", R"(<kml xmlns="http://www.opengis.net/kml/2.2"><Placemark><Model><Link><href>models/duck.dae</href></Link></Model></Placemark></kml>)"},
             {"models/duck.dae", slurp(models / "Collada" / "duck.dae")},
             {"models/duckCM.tga", slurp(models / "Collada" / "duckCM.tga")}}) {
        VSILFILE* f = VSIFOpenL(("/vsizip/" + kmz.string() + "/" + name).c_str(), "wb");
        ASSERT_NE(f, nullptr) << name;
        VSIFWriteL(bytes.data(), 1, bytes.size(), f);
        VSIFCloseL(f);
    }
    const auto at = [](double east) { return std::string("[").append(std::to_string(7.0 + east / 77000.0)).append(", 46.0, 0.0]"); };
    auto s = load(R"({"viewpoint": {"lon": 7.0000325, "lat": 46.0, "height": 0, "heading": 0, "pitch": -12, "range": 14},
        "time": {"start": "2026-03-20T10:00:00Z"},
        "layers": [{"type": "globe", "name": "Earth"},
                   {"type": "model", "name": "Duck", "file": )" + jsonString(kmz) + R"(, "position": )" + at(0.0) + R"(, "attitude": [200, 0, 0]},
                   {"type": "model", "name": "Wuson", "file": )" + jsonString(models / "STL" / "Wuson.stl") + R"(, "position": )" + at(2.5) + R"(, "attitude": [180, 0, 0]},
                   {"type": "model", "name": "Spider", "file": )" + jsonString(models / "FBX" / "spider.fbx") + R"(, "position": )" + at(-3.0) + R"(, "scale": 0.015, "attitude": [180, 0, 0]}]})");
    ASSERT_TRUE(s);
    EXPECT_TRUE(matchesGolden(render(*s, 400, 240), "model_mesh_formats_stl_fbx_kmz"));
    fs::remove_all(dir);
}

// A texture's wrap modes from a mesh file: two quads whose u runs from -1 to 2 under a texture
// red on its left half and blue on its right, one repeating (the MTL's default), one clamped
// (`-clamp on`): seen from above, red and blue alternate three times along the first and
// change once along the second.
TEST_F(ModelRender, MeshTexturesRepeatOrClampAsTheirMaterialSays) {
    const fs::path dir = fs::path(testOutputDir()) / ("model-wrap-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    ImageRgba8 tex{2, 1, {230, 20, 20, 255, 20, 20, 230, 255}};
    ASSERT_TRUE(writePng(dir / "halves.png", tex));
    std::ofstream(dir / "quads.mtl") << "newmtl Repeat\nKd 1 1 1\nmap_Kd halves.png\nnewmtl Clamp\nKd 1 1 1\nmap_Kd -clamp on halves.png\n";
    // Two 3 m x 1 m quads lying flat (y up), 0.5 m apart along z; u from -1 to 2 along x.
    std::ofstream(dir / "quads.obj") << "mtllib quads.mtl\n"
                                        "v -1.5 0 -1.25\nv 1.5 0 -1.25\nv 1.5 0 -0.25\nv -1.5 0 -0.25\n"
                                        "v -1.5 0 0.25\nv 1.5 0 0.25\nv 1.5 0 1.25\nv -1.5 0 1.25\n"
                                        "vt -1 0\nvt 2 0\nvt 2 1\nvt -1 1\nvn 0 1 0\n"
                                        "usemtl Repeat\nf 4/4/1 3/3/1 2/2/1 1/1/1\nusemtl Clamp\nf 8/4/1 7/3/1 6/2/1 5/1/1\n";
    auto s = load(R"({"viewpoint": {"lon": 7.0, "lat": 46.0, "height": 0, "heading": 0, "pitch": -89.9, "range": 5},
        "time": {"start": "2026-03-20T12:00:00Z"},
        "layers": [{"type": "globe", "name": "Earth"},
                   {"type": "model", "name": "Quads", "file": )" + jsonString(dir / "quads.obj") + R"(, "position": [7.0, 46.0, 0.2]}]})");
    ASSERT_TRUE(s);
    const ImageRgba8 image = render(*s, 320, 200);
    // Along each row and column: how often the colour turns between red and blue.
    const auto turns = [&](bool row, uint32_t at) {
        int count = 0, last = 0;
        const uint32_t n = row ? image.width : image.height;
        for (uint32_t i = 0; i < n; ++i) {
            const uint8_t* p = &image.pixels[4 * size_t(row ? at * image.width + i : i * image.width + at)];
            const int red = p[0] > 120 && p[0] > p[2] + 60, blue = p[2] > 120 && p[2] > p[0] + 60;
            const int now = red ? 1 : blue ? -1 : 0;
            if (now != 0 && last != 0 && now != last) ++count;
            if (now != 0) last = now;
        }
        return count;
    };
    std::vector<int> seen;
    for (uint32_t y = 0; y < image.height; y += 4) seen.push_back(turns(true, y));
    for (uint32_t x = 0; x < image.width; x += 4) seen.push_back(turns(false, x));
    const int most = *std::max_element(seen.begin(), seen.end());
    const size_t once = size_t(std::count(seen.begin(), seen.end(), 1));
    EXPECT_EQ(most, 5) << "repeat: red blue red blue red blue";
    EXPECT_GT(once, 5u) << "clamp: red, then blue";
    EXPECT_TRUE(matchesGolden(image, "model_texture_wrap"));
    fs::remove_all(dir);
}

TEST_F(ModelRender, BrokenModelsAndSettingsGiveClearErrors) {
    const fs::path dir = fs::path(testOutputDir()) / ("model-errors-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "broken.gltf") << R"({"asset": {"version": "2.0"}, "meshes": [)";
    auto expectError = [&](const std::string& layer, const std::string& needle) {
        auto desc = scene::parseSceneText(R"({"layers": [)" + layer + "]}", "test.json", ".");
        ASSERT_TRUE(desc) << desc.message();
        auto s = scene::Scene::build(std::move(*desc), registry_);
        ASSERT_FALSE(s) << layer;
        EXPECT_NE(s.message().find(needle), std::string::npos) << s.message();
    };
    const std::string wagon = jsonString(kSource / "assets/models/wagon.gltf");
    expectError(R"({"type": "model", "name": "M", "file": )" + jsonString(dir / "broken.gltf") + R"(, "position": [0, 0, 0]})",
                "broken.gltf");
    expectError(R"({"type": "model", "name": "M", "file": )" + jsonString(dir / "missing.glb") + R"(, "position": [0, 0, 0]})",
                "missing.glb");
    expectError(R"({"type": "model", "name": "M", "file": )" + wagon + "}", "exactly one of");
    expectError(R"({"type": "model", "name": "M", "file": )" + wagon + R"(, "trajectory": "nothere.csv"})", "nothere.csv");
    expectError(R"({"type": "model", "name": "M", "file": )" + wagon + R"(, "live": {"url": "tcp://localhost:99999"}})", "99999");
    expectError(R"({"type": "model", "name": "M", "file": )" + wagon + R"(, "position": [0, 0, 0], "copies": {"count": 0}})",
                "count");
    fs::remove_all(dir);
}


// A model on a live NMEA feed from a server on 127.0.0.1 that plays a recorded track, stops,
// and comes back on the same port: the model and the follow camera stay on the latest fix.
TEST_F(ModelRender, LiveFeedMovesTheModelAndSurvivesAServerRestart) {

    auto server = std::make_unique<livefeed::test::TcpFeedServer>();
    ASSERT_TRUE(server->ok()) << server->error();
    const uint16_t port = server->port();
    const TimeNs start = parseIso8601("2026-03-20T10:00:00Z").value();
    auto s = load(R"({"time": {"start": "2026-03-20T10:00:00Z", "end": "2026-03-20T11:00:00Z", "current": "2026-03-20T11:00:00Z"},
        "camera": {"mode": "follow", "target": "Car"},
        "layers": [{"type": "globe", "name": "Earth"},
                   {"type": "model", "name": "Car", "file": )" + jsonString(kSource / "assets/models/wagon.gltf") +
                  R"(, "live": {"url": ")" + server->url() + R"(", "protocol": "nmea"}, "path": {"show": true}, "label": "Car"}]})");
    ASSERT_TRUE(s);
    auto& layer = dynamic_cast<layers::ModelLayer&>(*s->find("Car")->layer);
    const scene::GroundHeightFn none;
    render(*s, 160, 100);   // prepares the layer; the feed connects on its own thread
    EXPECT_FALSE(layer.trackedPose(s->time().now(), none)) << "no pose before the first fix";

    const livefeed::NmeaWriter writer;
    const auto track = livefeed::test::syntheticTrack(40, start, kNsPerSecond);
    auto playAndWait = [&](livefeed::test::TcpFeedServer& srv, int from, int to) {
        ASSERT_TRUE(srv.acceptClient()) << "the source connects";
        for (int i = from; i < to; ++i) ASSERT_TRUE(srv.send(writer.epoch(track[size_t(i)])));
        const livefeed::Fix& last = track[size_t(to - 1)];
        const glm::dvec3 want = globe::Ellipsoid::wgs84().toEcef(last.lonDeg, last.latDeg, *last.heightEllipsoid);
        const bool arrived = livefeed::test::waitUntil([&] {
            render(*s, 160, 100);
            const auto pose = layer.trackedPose(s->time().now(), none);
            return pose && glm::length(pose->position - want) < 0.05;
        }, std::chrono::seconds(10));
        EXPECT_TRUE(arrived) << layer.status();
    };
    playAndWait(*server, 0, 20);
    // The follow camera is behind the model now.
    const auto pose = layer.trackedPose(s->time().now(), none);
    ASSERT_TRUE(pose);
    const double d = glm::length(s->camera().position() - pose->position);
    EXPECT_GT(d, 5.0);
    EXPECT_LT(d, 200.0);
    render(*s, 160, 100);
    EXPECT_EQ(layer.itemsDrawn(), 1u) << "the model is in the follow camera's view; camera " << d << " m away";
    // The server goes away and comes back on the same port; the source reconnects.
    server.reset();
    render(*s, 160, 100);
    server = std::make_unique<livefeed::test::TcpFeedServer>(port);
    ASSERT_TRUE(server->ok()) << server->error();
    playAndWait(*server, 20, 40);
    EXPECT_NE(layer.status().find("1 reconnects"), std::string::npos) << layer.status();
    render(*s, 160, 100);
    const auto end = layer.trackedPose(s->time().now(), none);
    ASSERT_TRUE(end);
    EXPECT_EQ(layer.itemsDrawn(), 1u) << "camera " << glm::length(s->camera().position() - end->position) << " m away";
    std::printf("[ live ] %s\n", layer.status().c_str());
}

}  // namespace
}  // namespace orbis::test
