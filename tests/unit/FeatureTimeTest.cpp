#include "layers/vector/FeatureTime.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace orbis::vector {
namespace {

namespace fs = std::filesystem;

/// A file in a fresh temporary folder, removed with the object.
struct TempFile {
    fs::path dir, path;
    TempFile(const std::string& name, const std::string& text)
        : dir(fs::temp_directory_path() / ("orbis-feature-time-" + std::to_string(::getpid()) + "-" + name)), path(dir / name) {
        fs::create_directories(dir);
        std::ofstream(path) << text;
    }
    ~TempFile() { fs::remove_all(dir); }
};

VectorLayer readOne(const fs::path& file) {
    VectorReadOptions o;
    o.source = file.string();
    auto data = readVector(o);
    EXPECT_TRUE(data) << (data ? "" : data.message());
    return data ? data->layers.at(0) : VectorLayer{};
}

TimeNs at(const char* iso) { return *parseIso8601(iso); }

TEST(FeatureTime, KmlTimeStampsAndTimeSpansComeFromTheFile) {
    TempFile kml("timed.kml", R"KML(<?xml version="1.0" encoding="UTF-8"?>
<kml xmlns="http://www.opengis.net/kml/2.2"><Document>
  <Placemark><name>stamp</name><TimeStamp><when>2026-06-21T10:00:00Z</when></TimeStamp><Point><coordinates>9,46,0</coordinates></Point></Placemark>
  <Placemark><name>span</name><TimeSpan><begin>2026-06-21T09:00:00Z</begin><end>2026-06-21T11:00:00Z</end></TimeSpan><Point><coordinates>9.1,46,0</coordinates></Point></Placemark>
  <Placemark><name>always</name><Point><coordinates>9.2,46,0</coordinates></Point></Placemark>
</Document></kml>)KML");
    const VectorLayer layer = readOne(kml.path);
    ASSERT_EQ(layer.features.size(), 3u);
    auto times = featureTimes(layer, {});
    ASSERT_TRUE(times) << times.message();
    ASSERT_TRUE(times->timed());
    const FeatureTimeSpan &stamp = times->spans[0], &span = times->spans[1], &always = times->spans[2];
    // A TimeStamp shows from its time on; a TimeSpan from begin until end; no time, always.
    EXPECT_FALSE(stamp.shows(at("2026-06-21T09:59:59Z")));
    EXPECT_TRUE(stamp.shows(at("2026-06-21T10:00:00Z")));
    EXPECT_TRUE(stamp.shows(at("2027-01-01T00:00:00Z")));
    EXPECT_FALSE(span.shows(at("2026-06-21T08:59:59Z")));
    EXPECT_TRUE(span.shows(at("2026-06-21T09:00:00Z")));
    EXPECT_TRUE(span.shows(at("2026-06-21T10:59:59Z")));
    EXPECT_FALSE(span.shows(at("2026-06-21T11:00:00Z")));
    EXPECT_TRUE(always.always());
    EXPECT_EQ(times->first, at("2026-06-21T09:00:00Z"));
    EXPECT_EQ(times->last, at("2026-06-21T11:00:00Z"));
}

TEST(FeatureTime, FieldsTheSceneNamesHoldIsoTextOrUnixSeconds) {
    TempFile json("events.geojson", R"({"type": "FeatureCollection", "features": [
      {"type": "Feature", "properties": {"from": "2026-03-20T08:00:00+02:00", "to": 1774000000},
       "geometry": {"type": "Point", "coordinates": [1, 2]}},
      {"type": "Feature", "properties": {"from": null, "to": "2026-03-21"},
       "geometry": {"type": "Point", "coordinates": [3, 4]}},
      {"type": "Feature", "properties": {"from": "the day after", "to": null},
       "geometry": {"type": "Point", "coordinates": [5, 6]}}]})");
    const VectorLayer layer = readOne(json.path);
    ASSERT_EQ(layer.features.size(), 3u);
    auto times = featureTimes(layer, {.begin = "from", .end = "to"});
    ASSERT_TRUE(times) << times.message();
    EXPECT_EQ(times->spans[0].begin, at("2026-03-20T06:00:00Z"));
    EXPECT_EQ(times->spans[0].end, TimeNs(1774000000) * kNsPerSecond);
    EXPECT_FALSE(times->spans[1].begin);   // null: open
    EXPECT_EQ(times->spans[1].end, at("2026-03-21T00:00:00Z"));
    // Text that is not a time hides the feature, with a warning that names it.
    EXPECT_TRUE(times->spans[2].hidden);
    EXPECT_FALSE(times->spans[2].shows(at("2026-03-20T12:00:00Z")));
    ASSERT_EQ(times->warnings.size(), 1u);
    EXPECT_NE(times->warnings[0].find("feature 2: field 'from'"), std::string::npos) << times->warnings[0];
    EXPECT_NE(times->warnings[0].find("the day after"), std::string::npos) << times->warnings[0];
}

TEST(FeatureTime, ALayerWithoutTimesAndAMissingField) {
    TempFile json("plain.geojson", R"({"type": "FeatureCollection", "features": [
      {"type": "Feature", "properties": {"name": "a"}, "geometry": {"type": "Point", "coordinates": [1, 2]}}]})");
    const VectorLayer layer = readOne(json.path);
    auto none = featureTimes(layer, {});
    ASSERT_TRUE(none);
    EXPECT_FALSE(none->timed());
    auto missing = featureTimes(layer, {.begin = "date"});
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.message(), "layer 'plain' has no time field 'date' (its fields: name)");
}

}  // namespace
}  // namespace orbis::vector
