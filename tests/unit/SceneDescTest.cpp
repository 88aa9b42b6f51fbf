// Scene files: every malformed input gives one clear message naming the file, the JSON path and
// the problem; nothing throws or crashes.
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/Scene.h"
#include "engine/scene/SceneDesc.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace orbis::scene {
namespace {

Result<SceneDesc> parse(const std::string& text) { return parseSceneText(text, "s.json", "/data/scenes"); }

::testing::AssertionResult failsWith(const std::string& text, const std::string& expected) {
    auto r = parse(text);
    if (r.ok()) return ::testing::AssertionFailure() << "parsed without error: " << text;
    if (r.message().find(expected) == std::string::npos)
        return ::testing::AssertionFailure() << "message '" << r.message() << "' lacks '" << expected << "'";
    if (r.message().rfind("s.json: ", 0) != 0)
        return ::testing::AssertionFailure() << "message does not start with the file name: " << r.message();
    return ::testing::AssertionSuccess();
}

TEST(SceneDesc, MinimalSceneGetsDefaults) {
    auto r = parse(R"({"layers": []})");
    ASSERT_TRUE(r.ok()) << r.message();
    EXPECT_EQ(r->layers.size(), 0u);
    EXPECT_DOUBLE_EQ(r->fovDeg, 45.0);
    EXPECT_EQ(r->time.start, r->time.end);
    EXPECT_EQ(r->folder, "/data/scenes");
}

TEST(SceneDesc, FullSceneIsRead) {
    auto r = parse(R"({"orbis": 1, "name": "N", "fovDeg": 30,
        "viewpoint": {"lon": 10, "lat": -20, "height": 5, "heading": 45, "pitch": -30, "range": 1000},
        "time": {"start": "2026-01-01T00:00:00Z", "end": "2026-01-02T00:00:00Z", "current": "2026-01-01T06:00:00Z",
                 "rate": 10, "loop": true, "playing": true},
        "background": [0.1, 0.2, 0.3],
        "layers": [{"type": "globe", "name": "E", "visible": false, "viewpoint": {"lon": 1, "lat": 2, "range": 3},
                    "graticuleDeg": 10}]})");
    ASSERT_TRUE(r.ok()) << r.message();
    EXPECT_EQ(r->name, "N");
    EXPECT_DOUBLE_EQ(r->viewpoint.headingDeg, 45.0);
    EXPECT_DOUBLE_EQ(r->viewpoint.range, 1000.0);
    EXPECT_EQ(r->time.current - r->time.start, 6ll * 3600 * 1000000000ll);
    EXPECT_TRUE(r->time.loop);
    ASSERT_EQ(r->layers.size(), 1u);
    EXPECT_EQ(r->layers[0].type, "globe");
    EXPECT_FALSE(r->layers[0].visible);
    ASSERT_TRUE(r->layers[0].viewpoint.has_value());
    EXPECT_DOUBLE_EQ(r->layers[0].viewpoint->range, 3.0);
    EXPECT_EQ(r->layers[0].settings["graticuleDeg"], 10);
    EXPECT_EQ(r->layers[0].jsonPath, "/layers/0");
}

TEST(SceneDesc, MalformedJsonNamesLineAndColumn) {
    EXPECT_TRUE(failsWith("{\n  \"layers\": [,]\n}", "line 2"));
    EXPECT_TRUE(failsWith("", "line 1"));
    EXPECT_TRUE(failsWith("{\"layers\": [] ", "syntax error"));
}

TEST(SceneDesc, SyntaxErrorReadsFileLineColumnAndTheParsersWords) {
    // The position is counted from 1; the parser's own "[json.exception...] parse error at ..."
    // prefix is dropped.
    EXPECT_EQ(parse("{\n  \"layers\": [,]\n}").message(),
              "s.json: line 2, column 14: syntax error while parsing value - unexpected ','; expected '[', '{', or a literal");
}

// A number too large for a double is not a syntax error: nlohmann threw out_of_range, and the
// message named neither the file nor the key (../shared/data/bad/scene-tiny-overflow.json).
TEST(SceneDesc, NumberOverflowNamesFileKeyAndPlace) {
    EXPECT_EQ(parse("{\"orbis\": 1, \"layers\": [{\"type\": \"globe\"},\n {\"type\": \"globe\", \"graticuleDeg\": -1e400}]}").message(),
              "s.json: /layers/1/graticuleDeg (line 2, column 36): number overflow parsing '-1e400'");
    EXPECT_EQ(parse("{\"fovDeg\": 1e309}").message(), "s.json: /fovDeg (line 1, column 12): number overflow parsing '1e309'");
    EXPECT_EQ(parse("[[1, 2], [3, 1e999]]").message(), "s.json: /1/1 (line 1, column 14): number overflow parsing '1e999'");
    EXPECT_EQ(parse("1e999").message(), "s.json: / (line 1, column 1): number overflow parsing '1e999'");
}

// Found by fuzz-scene: a version too large for an integer was converted to one to be printed
// (UBSan: -5e+200 is outside the range of long long).
TEST(SceneDesc, AnyVersionNumberIsNamedAsWritten) {
    EXPECT_EQ(parse("{\"orbis\": -5.0e200}").message(), "s.json: /orbis: scene format version -5e+200 is not supported (this build reads 1)");
    EXPECT_EQ(parse("{\"orbis\": 2}").message(), "s.json: /orbis: scene format version 2 is not supported (this build reads 1)");
    EXPECT_EQ(parse("{\"orbis\": 1.5}").message(), "s.json: /orbis: scene format version 1.5 is not supported (this build reads 1)");
}

TEST(SceneDesc, WrongTypesNameThePath) {
    EXPECT_TRUE(failsWith(R"({"layers": {}})", "/layers: expected an array, got an object"));
    EXPECT_TRUE(failsWith(R"({"layers": [{"type": 3}]})", "/layers/0/type: expected a string, got a number"));
    EXPECT_TRUE(failsWith(R"({"layers": [{"type": "globe", "visible": "yes"}]})", "/layers/0/visible: expected a boolean"));
    EXPECT_TRUE(failsWith(R"({"fovDeg": "wide", "layers": []})", "/fovDeg: expected a number, got a string"));
    EXPECT_TRUE(failsWith(R"({"viewpoint": {"lat": 91}, "layers": []})", "/viewpoint/lat: value 91 is out of range"));
    EXPECT_TRUE(failsWith(R"({"viewpoint": {"range": -1}, "layers": []})", "/viewpoint/range"));
    EXPECT_TRUE(failsWith(R"({"background": [1, 2], "layers": []})", "/background: expected an array of 3 numbers"));
    EXPECT_TRUE(failsWith(R"([1, 2])", "expected an object, got an array"));
    EXPECT_TRUE(failsWith(R"({"layers": [7]})", "/layers/0: expected an object, got a number"));
}

TEST(SceneDesc, MissingAndUnknownKeysAreErrors) {
    EXPECT_TRUE(failsWith(R"({})", "/layers: missing"));
    EXPECT_TRUE(failsWith(R"({"layers": [{"name": "x"}]})", "/layers/0/type: missing"));
    EXPECT_TRUE(failsWith(R"({"layrs": [], "layers": []})", "unknown key 'layrs'"));
    EXPECT_TRUE(failsWith(R"({"viewpoint": {"lng": 3}, "layers": []})", "/viewpoint/lng: unknown key"));
    EXPECT_TRUE(failsWith(R"({"orbis": 2, "layers": []})", "version 2 is not supported"));
}

TEST(SceneDesc, BadTimesAreErrors) {
    EXPECT_TRUE(failsWith(R"({"time": {"start": "yesterday"}, "layers": []})", "/time/start"));
    EXPECT_TRUE(failsWith(R"({"time": {"start": "2026-01-02T00:00:00Z", "end": "2026-01-01T00:00:00Z"}, "layers": []})",
                          "/time/end: the end time is before the start time"));
    EXPECT_TRUE(failsWith(R"({"time": {"start": "2026-01-01T00:00:00Z", "end": "2026-01-02T00:00:00Z",
                                       "current": "2027-01-01T00:00:00Z"}, "layers": []})",
                          "/time/current"));
}

TEST(SceneDesc, MissingFileAndFolderAreErrors) {
    auto missing = parseSceneFile("/nonexistent/scene.json");
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.message(), "/nonexistent/scene.json: no such file");
    auto folder = parseSceneFile(std::filesystem::temp_directory_path());
    ASSERT_FALSE(folder.ok());
    EXPECT_NE(folder.message().find("is a folder"), std::string::npos);
}

TEST(SceneDesc, BinaryGarbageIsAnErrorNotACrash) {
    const auto file = std::filesystem::temp_directory_path() / "orbis_garbage_scene.json";
    {
        std::ofstream out(file, std::ios::binary);
        for (int i = 0; i < 4096; ++i) out.put(static_cast<char>((i * 7919) & 0xff));
    }
    auto r = parseSceneFile(file);
    EXPECT_FALSE(r.ok());
    std::filesystem::remove(file);
}

TEST(SceneDesc, RelativePathsResolveAgainstTheSceneFolder) {
    auto r = parse(R"({"layers": []})");
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->resolve("data/dem.tif"), "/data/scenes/data/dem.tif");
    EXPECT_EQ(r->resolve("../x.tif"), "/data/x.tif");
    EXPECT_EQ(r->resolve("/abs/y.tif"), "/abs/y.tif");
    // Sources that are not files stay as they are (a relative path would mangle "//").
    EXPECT_EQ(r->resolveSource("data/dem.tif"), "/data/scenes/data/dem.tif");
    const std::string wms = "WMS:http://127.0.0.1:8080/ows?SERVICE=WMS&LAYERS=world&SRS=EPSG:4326&BBOX=-180,-90,180,90";
    EXPECT_EQ(r->resolveSource(wms), wms);
    EXPECT_EQ(r->resolveSource("https://example.org/dem.tif"), "https://example.org/dem.tif");
    EXPECT_EQ(r->resolveSource("/vsicurl/http://h/x.tif"), "/vsicurl/http://h/x.tif");
    EXPECT_EQ(r->resolveSource("<GDAL_WMS><Service name=\"TMS\"/></GDAL_WMS>"), "<GDAL_WMS><Service name=\"TMS\"/></GDAL_WMS>");
}

class CountingLayer : public Layer {
public:
    std::string_view type() const override { return "count"; }
    bool drawsIn(Pass) const override { return false; }
    void record(Pass, const render::RecordContext&) override {}

private:
    void onPrepare(const render::RenderServices&) override {}
};

TEST(LayerRegistry, UnknownTypeListsKnownTypes) {
    LayerRegistry registry;
    registry.add("count", "test", [](const LayerDesc&, const SceneDesc&) -> Result<std::unique_ptr<Layer>> {
        return std::unique_ptr<Layer>(new CountingLayer);
    });
    auto desc = parse(R"({"layers": [{"type": "volme"}]})");
    ASSERT_TRUE(desc.ok());
    auto scene = Scene::build(std::move(desc).value(), registry);
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.message(), "s.json: /layers/0/type: unknown layer type 'volme' (known: count)");
    EXPECT_EQ(registry.constructed("count"), 0);
}

TEST(LayerRegistry, OnlyNamedTypesAreConstructed) {
    LayerRegistry registry;
    for (const char* t : {"a", "b", "c"})
        registry.add(t, "test", [](const LayerDesc&, const SceneDesc&) -> Result<std::unique_ptr<Layer>> {
            return std::unique_ptr<Layer>(new CountingLayer);
        });
    auto desc = parse(R"({"layers": [{"type": "b", "name": "one"}, {"type": "b", "name": "two"}]})");
    ASSERT_TRUE(desc.ok());
    auto scene = Scene::build(std::move(desc).value(), registry);
    ASSERT_TRUE(scene.ok()) << scene.message();
    EXPECT_EQ(registry.constructed("a"), 0);
    EXPECT_EQ(registry.constructed("b"), 2);
    EXPECT_EQ(registry.constructed("c"), 0);
    ASSERT_EQ((*scene)->resources().size(), 2u);
    EXPECT_EQ((*scene)->resources()[1].name, "two");
    EXPECT_NE((*scene)->find("one"), nullptr);
}

TEST(LayerRegistry, FactoryErrorsReachTheCaller) {
    LayerRegistry registry;
    registry.add("bad", "test", [](const LayerDesc& l, const SceneDesc& s) -> Result<std::unique_ptr<Layer>> {
        return Error{s.file.string() + ": " + l.jsonPath + "/file: cannot open"};
    });
    auto desc = parse(R"({"layers": [{"type": "bad"}]})");
    ASSERT_TRUE(desc.ok());
    auto scene = Scene::build(std::move(desc).value(), registry);
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.message(), "s.json: /layers/0/file: cannot open");
}

TEST(LayerRegistry, KeepGoingLeavesAFailedLayerWithItsErrorAndLoadsTheOthers) {
    LayerRegistry registry;
    registry.add("bad", "test", [](const LayerDesc& l, const SceneDesc& s) -> Result<std::unique_ptr<Layer>> {
        return Error{s.file.string() + ": " + l.jsonPath + "/file: cannot open"};
    });
    registry.add("good", "test", [](const LayerDesc&, const SceneDesc&) -> Result<std::unique_ptr<Layer>> {
        return std::unique_ptr<Layer>(new CountingLayer);
    });
    auto desc = parse(R"({"layers": [{"type": "bad", "name": "Broken"}, {"type": "good", "name": "Fine"},
                                     {"type": "nope", "name": "Unknown"}]})");
    ASSERT_TRUE(desc.ok());
    auto scene = Scene::build(std::move(desc).value(), registry, {.keepGoing = true});
    ASSERT_TRUE(scene.ok()) << scene.message();
    const auto& r = (*scene)->resources();
    ASSERT_EQ(r.size(), 3u);
    EXPECT_EQ(r[0].error, "s.json: /layers/0/file: cannot open");
    EXPECT_FALSE(r[0].visible);
    ASSERT_NE(r[0].layer, nullptr) << "a stand-in that draws nothing, so no caller meets a null layer";
    EXPECT_EQ(r[0].layer->type(), "bad");
    EXPECT_FALSE(r[0].layer->drawsIn(Pass::Opaque));
    EXPECT_NE(r[0].layer->status().find("cannot open"), std::string::npos);
    EXPECT_TRUE(r[1].error.empty());
    EXPECT_TRUE(r[1].visible);
    EXPECT_NE(r[2].error.find("unknown layer type 'nope'"), std::string::npos) << r[2].error;
}

}  // namespace
}  // namespace orbis::scene
