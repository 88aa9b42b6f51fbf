// The scene's "annotations" (labelled pins): read when well formed, and every malformed pin is
// one clear message naming the file, the pin's JSON path and the problem.
#include "engine/scene/SceneDesc.h"

#include <gtest/gtest.h>

namespace orbis::scene {
namespace {

Result<SceneDesc> parse(const std::string& annotations) {
    return parseSceneText(R"({"annotations": )" + annotations + R"(, "layers": []})", "pins.json", "/data");
}

::testing::AssertionResult failsWith(const std::string& annotations, const std::string& expected) {
    auto r = parse(annotations);
    if (r.ok()) return ::testing::AssertionFailure() << "parsed without error: " << annotations;
    if (r.message().rfind("pins.json: ", 0) != 0 || r.message().find(expected) == std::string::npos)
        return ::testing::AssertionFailure() << "message '" << r.message() << "' lacks 'pins.json: ... " << expected << "'";
    return ::testing::AssertionSuccess();
}

TEST(SceneAnnotations, PinsAreRead) {
    auto r = parse(R"([{"name": "Summit", "lon": 7, "lat": 46, "height": 4000}, {"name": "Pole", "lon": -180, "lat": -90}])");
    ASSERT_TRUE(r.ok()) << r.message();
    ASSERT_EQ(r->annotations.size(), 2u);
    EXPECT_EQ(r->annotations[0].name, "Summit");
    EXPECT_DOUBLE_EQ(r->annotations[0].lonDeg, 7.0);
    EXPECT_DOUBLE_EQ(r->annotations[0].latDeg, 46.0);
    EXPECT_DOUBLE_EQ(r->annotations[0].height, 4000.0);
    EXPECT_DOUBLE_EQ(r->annotations[1].height, 0.0) << "height defaults to the ellipsoid";
}

TEST(SceneAnnotations, NoneIsAnEmptyList) {
    auto r = parseSceneText(R"({"layers": []})", "pins.json", "/data");
    ASSERT_TRUE(r.ok()) << r.message();
    EXPECT_TRUE(r->annotations.empty());
    EXPECT_TRUE(parse("[]").ok());
}

TEST(SceneAnnotations, MalformedPinsNameThePath) {
    EXPECT_TRUE(failsWith(R"({"name": "x"})", "/annotations: expected an array, got an object"));
    EXPECT_TRUE(failsWith(R"([7])", "/annotations/0: expected an object, got a number"));
    EXPECT_TRUE(failsWith(R"([{"lon": 1, "lat": 2}])", "/annotations/0/name: missing; expected a string"));
    EXPECT_TRUE(failsWith(R"([{"name": "", "lon": 1, "lat": 2}])", "/annotations/0/name: must not be empty"));
    EXPECT_TRUE(failsWith(R"([{"name": 5, "lon": 1, "lat": 2}])", "/annotations/0/name: expected a string, got a number"));
    EXPECT_TRUE(failsWith(R"([{"name": "a", "lon": 1, "lat": 2}, {"name": "b", "lat": 2}])",
                          "/annotations/1/lon: missing; expected a number"));
    EXPECT_TRUE(failsWith(R"([{"name": "a", "lon": 1}])", "/annotations/0/lat: missing"));
    EXPECT_TRUE(failsWith(R"([{"name": "a", "lon": 181, "lat": 0}])", "/annotations/0/lon: value 181 is out of range [-180"));
    EXPECT_TRUE(failsWith(R"([{"name": "a", "lon": 0, "lat": -91}])", "/annotations/0/lat: value -91 is out of range"));
    EXPECT_TRUE(failsWith(R"([{"name": "a", "lon": 0, "lat": 0, "height": "high"}])", "/annotations/0/height: expected a number"));
    EXPECT_TRUE(failsWith(R"([{"name": "a", "lon": 0, "lat": 0, "label": "typo"}])", "/annotations/0/label: unknown key 'label'"));
}

}  // namespace
}  // namespace orbis::scene
