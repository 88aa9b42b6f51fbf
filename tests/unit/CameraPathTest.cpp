// Scripted camera paths: parsing with clear errors, exact keys, continuous and clamped playback.
#include "engine/scene/CameraPath.h"
#include "globe/EarthManipulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace orbis::scene {
namespace {

const char* kThreeKeys = R"({"orbis-camera-path": 1, "interpolation": "smooth", "keys": [
    {"t": 0, "viewpoint": {"lon": 10, "lat": 45, "height": 0, "heading": 0, "pitch": -90, "range": 2e7}},
    {"t": 12, "viewpoint": {"lon": 11, "lat": 46, "height": 300, "heading": 90, "pitch": -30, "range": 5000}},
    {"t": 20, "viewpoint": {"lon": 11.5, "lat": 46.2, "heading": 120, "pitch": -20, "range": 1500}}]})";

Result<CameraPath> parse(const std::string& text) { return CameraPath::parseText(text, "p.json"); }

::testing::AssertionResult failsWith(const std::string& text, const std::string& expected) {
    auto r = parse(text);
    if (r.ok()) return ::testing::AssertionFailure() << "parsed without error: " << text;
    if (r.message().find(expected) == std::string::npos)
        return ::testing::AssertionFailure() << "message '" << r.message() << "' lacks '" << expected << "'";
    if (r.message().rfind("p.json: ", 0) != 0)
        return ::testing::AssertionFailure() << "message does not start with the file name: " << r.message();
    return ::testing::AssertionSuccess();
}

std::string twoKeys(const std::string& first, const std::string& second, const std::string& extra = "") {
    return R"({"orbis-camera-path": 1)" + extra + R"(, "keys": [)" + first + ", " + second + "]}";
}

void expectSame(const globe::Viewpoint& a, const globe::Viewpoint& b) {
    EXPECT_EQ(a.lonDeg, b.lonDeg);
    EXPECT_EQ(a.latDeg, b.latDeg);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.headingDeg, b.headingDeg);
    EXPECT_EQ(a.pitchDeg, b.pitchDeg);
    EXPECT_EQ(a.range, b.range);
}

TEST(CameraPath, ParsesKeysAndInterpolation) {
    auto r = parse(kThreeKeys);
    ASSERT_TRUE(r.ok()) << r.message();
    EXPECT_EQ(r->size(), 3u);
    EXPECT_DOUBLE_EQ(r->duration(), 20.0);
    EXPECT_EQ(r->interpolation(), CameraPath::Interpolation::Smooth);
    EXPECT_DOUBLE_EQ(r->keys()[1].viewpoint.height, 300.0);
    EXPECT_DOUBLE_EQ(r->keys()[2].viewpoint.height, 0.0);   // readViewpoint's default
    auto linear = parse(twoKeys(R"({"t": 1, "viewpoint": {}})", R"({"t": 3, "viewpoint": {"lon": 5}})", R"(, "interpolation": "linear")"));
    ASSERT_TRUE(linear.ok()) << linear.message();
    EXPECT_EQ(linear->interpolation(), CameraPath::Interpolation::Linear);
    EXPECT_DOUBLE_EQ(linear->startTime(), 1.0);
    EXPECT_DOUBLE_EQ(linear->duration(), 2.0);
}

TEST(CameraPath, RejectsTimesThatDoNotIncrease) {
    auto r = parse(R"({"orbis-camera-path": 1, "keys": [
        {"t": 0, "viewpoint": {}}, {"t": 12, "viewpoint": {}}, {"t": 12, "viewpoint": {}}]})");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.message(), "p.json: /keys/2/t: must be greater than the previous key's t (12)");
    EXPECT_TRUE(failsWith(twoKeys(R"({"t": 5, "viewpoint": {}})", R"({"t": 2.5, "viewpoint": {}})"),
                          "/keys/1/t: must be greater than the previous key's t (5)"));
    EXPECT_TRUE(failsWith(twoKeys(R"({"t": -1, "viewpoint": {}})", R"({"t": 2, "viewpoint": {}})"), "/keys/0/t: value -1"));
}

TEST(CameraPath, NeedsAtLeastTwoKeys) {
    EXPECT_TRUE(failsWith(R"({"orbis-camera-path": 1, "keys": [{"t": 0, "viewpoint": {}}]})",
                          "/keys: a camera path needs at least 2 keys, got 1"));
    EXPECT_TRUE(failsWith(R"({"orbis-camera-path": 1, "keys": []})", "at least 2 keys, got 0"));
    EXPECT_TRUE(failsWith(R"({"orbis-camera-path": 1})", "/keys: missing"));
}

TEST(CameraPath, RejectsAKeyWithoutViewpointOrTime) {
    EXPECT_TRUE(failsWith(twoKeys(R"({"t": 0, "viewpoint": {}})", R"({"t": 1})"), "/keys/1/viewpoint: missing; expected an object"));
    EXPECT_TRUE(failsWith(twoKeys(R"({"viewpoint": {}})", R"({"t": 1, "viewpoint": {}})"), "/keys/0/t: missing; expected a number"));
    EXPECT_TRUE(failsWith(twoKeys(R"({"t": 0, "viewpoint": {}})", R"(3)"), "/keys/1: expected an object, got a number"));
    EXPECT_TRUE(failsWith(twoKeys(R"({"t": 0, "viewpoint": {"lat": 95}})", R"({"t": 1, "viewpoint": {}})"),
                          "/keys/0/viewpoint/lat: value 95"));
}

TEST(CameraPath, RejectsUnknownKeysAnywhere) {
    EXPECT_TRUE(failsWith(twoKeys(R"({"t": 0, "viewpoint": {}})", R"({"t": 1, "viewpoint": {}})", R"(, "interpolaton": "linear")"),
                          "/interpolaton: unknown key"));
    EXPECT_TRUE(failsWith(twoKeys(R"({"t": 0, "time": 3, "viewpoint": {}})", R"({"t": 1, "viewpoint": {}})"),
                          "/keys/0/time: unknown key"));
    EXPECT_TRUE(failsWith(twoKeys(R"({"t": 0, "viewpoint": {"lng": 3}})", R"({"t": 1, "viewpoint": {}})"),
                          "/keys/0/viewpoint/lng: unknown key"));
}

TEST(CameraPath, RejectsBadJsonVersionAndInterpolation) {
    EXPECT_TRUE(failsWith("{\n  \"keys\": [,]\n}", "line 2"));
    EXPECT_TRUE(failsWith("[1, 2]", "expected an object, got an array"));
    std::string version2 = twoKeys(R"({"t": 0, "viewpoint": {}})", R"({"t": 1, "viewpoint": {}})");
    version2[version2.find(": 1") + 2] = '2';   // the format version, the first number
    EXPECT_TRUE(failsWith(version2, "camera path format version 2 is not supported"));
    EXPECT_TRUE(failsWith(R"({"keys": []})", "/orbis-camera-path: missing"));
    EXPECT_TRUE(failsWith(twoKeys(R"({"t": 0, "viewpoint": {}})", R"({"t": 1, "viewpoint": {}})", R"(, "interpolation": "cubic")"),
                          R"(/interpolation: expected "smooth" or "linear", got "cubic")"));
}

TEST(CameraPath, NumberOverflowNamesTheKey) {
    EXPECT_EQ(CameraPath::parseText("{\"keys\": [{\"t\": 0}, {\"t\": 1, \"viewpoint\": {\"range\": 1e309}}]}", "p.json").message(),
              "p.json: /keys/1/viewpoint/range (line 1, column 53): number overflow parsing '1e309'");
}

TEST(CameraPath, SyntaxErrorNamesFileLineAndColumn) {
    EXPECT_EQ(CameraPath::parseText("{\n  \"keys\": [,]\n}", "p.json").message(),
              "p.json: line 2, column 12: syntax error while parsing value - unexpected ','; expected '[', '{', or a literal");
}

TEST(CameraPath, AtKeyTimesGivesTheKeysExactly) {
    auto r = parse(kThreeKeys);
    ASSERT_TRUE(r.ok()) << r.message();
    for (const auto& key : r->keys()) expectSame(r->at(key.t), key.viewpoint);
}

TEST(CameraPath, IsContinuousBetweenKeys) {
    // Steps of 1 ms never move the viewpoint by more than the fastest leg allows (range: 2e7 m
    // over 12 s, at most 1.5x the mean speed with easing: 2.5 km per ms), and 1 us either side of
    // a key is within 1 us of travel of the key (5 m of range, 1e-5 degrees).
    for (const char* interp : {"smooth", "linear"}) {
        std::string text = kThreeKeys;
        text.replace(text.find("smooth"), 6, interp);
        auto r = parse(text);
        ASSERT_TRUE(r.ok()) << r.message();
        globe::Viewpoint last = r->at(0.0);
        for (double t = 0.001; t <= 20.0; t += 0.001) {
            const globe::Viewpoint v = r->at(t);
            ASSERT_NEAR(v.lonDeg, last.lonDeg, 1e-3) << interp << " t=" << t;
            ASSERT_NEAR(v.latDeg, last.latDeg, 1e-3) << t;
            ASSERT_NEAR(std::remainder(v.headingDeg - last.headingDeg, 360.0), 0.0, 0.1) << t;
            ASSERT_NEAR(v.range, last.range, 3000.0) << t;
            last = v;
        }
        for (const auto& key : r->keys()) {
            for (double dt : {-1e-6, 1e-6}) {
                const globe::Viewpoint v = r->at(key.t + dt);
                EXPECT_NEAR(v.lonDeg, key.viewpoint.lonDeg, 1e-5) << interp << " " << key.t + dt;
                EXPECT_NEAR(v.latDeg, key.viewpoint.latDeg, 1e-5);
                EXPECT_NEAR(std::remainder(v.headingDeg - key.viewpoint.headingDeg, 360.0), 0.0, 1e-4);
                EXPECT_NEAR(v.pitchDeg, key.viewpoint.pitchDeg, 1e-4);
                EXPECT_NEAR(v.range, key.viewpoint.range, 5.0);
            }
        }
        // Halfway through a smooth leg is halfway (easing is symmetric); a quarter is not.
        const globe::Viewpoint quarter = r->at(3.0);
        const double u = (quarter.headingDeg - 0.0) / 90.0;
        EXPECT_NEAR(u, std::string(interp) == "smooth" ? 0.15625 : 0.25, 1e-9);
    }
}

TEST(CameraPath, BetweenKeysFollowsTheFlightInterpolation) {
    auto r = parse(kThreeKeys);
    ASSERT_TRUE(r.ok()) << r.message();
    const auto& k = r->keys();
    // 15 s is 3/8 of the way from the key at 12 s to the one at 20 s.
    expectSame(r->at(15.0), globe::interpolateFlight(k[1].viewpoint, k[2].viewpoint, globe::easeInOut(0.375)));
    std::string text = kThreeKeys;
    text.replace(text.find("smooth"), 6, "linear");
    auto linear = parse(text);
    ASSERT_TRUE(linear.ok()) << linear.message();
    expectSame(linear->at(15.0), globe::interpolateFlight(k[1].viewpoint, k[2].viewpoint, 0.375));
}

TEST(CameraPath, ClampsBeforeTheStartAndAfterTheEnd) {
    auto r = parse(kThreeKeys);
    ASSERT_TRUE(r.ok()) << r.message();
    expectSame(r->at(-5.0), r->keys().front().viewpoint);
    expectSame(r->at(1e9), r->keys().back().viewpoint);
    expectSame(r->at(std::nan("")), r->keys().front().viewpoint);
}

TEST(CameraPath, ParseFileReadsAFileAndNamesAMissingOne) {
    // A folder of its own: other build trees may run this test at the same time.
    const auto dir = std::filesystem::temp_directory_path() / ("orbis_camera_path_test_" + std::to_string(std::random_device{}()));
    std::filesystem::create_directories(dir);
    const auto file = dir / "flight.json";
    std::ofstream(file) << kThreeKeys;
    auto r = CameraPath::parseFile(file);
    ASSERT_TRUE(r.ok()) << r.message();
    EXPECT_EQ(r->size(), 3u);
    const auto missing = CameraPath::parseFile(dir / "nope.json");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.message().find("nope.json: no such file"), std::string::npos);
    std::ofstream(file) << R"({"orbis-camera-path": 1, "keys": [{"t": 0, "viewpoint": {}}]})";
    const auto bad = CameraPath::parseFile(file);
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.message().rfind(file.string() + ": /keys:", 0), 0u) << bad.message();
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace orbis::scene
