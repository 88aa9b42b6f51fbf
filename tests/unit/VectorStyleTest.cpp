#include "layers/vector/VectorStyle.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace orbis::vector {
namespace {

using nlohmann::json;

const std::vector<FieldInfo> kFields = {{"name", "String"}, {"pop", "Integer64"}, {"height", "Real"}, {"kind", "String"}};

std::vector<AttributeValue> attrs(std::string name, int64_t pop, AttributeValue height, std::string kind) {
    return {AttributeValue{std::move(name)}, AttributeValue{pop}, std::move(height), AttributeValue{std::move(kind)}};
}

Result<VectorStyle> styleFrom(const std::string& text) {
    static json keep;   // the reader keeps no reference after read()
    keep = json::parse(text);
    auto style = VectorStyle::read(&keep, "scene.json", "/layers/1/style");
    if (!style) return style.error();
    if (auto bound = style->bind(kFields, "cities"); !bound) return bound.error();
    return style;
}

TEST(VectorStyle, DefaultsWithoutAStyleObject) {
    auto style = VectorStyle::read(nullptr, "scene.json", "/layers/0/style");
    ASSERT_TRUE(style) << style.message();
    ASSERT_TRUE(style->bind(kFields, "cities"));
    const FeatureStyle s = style->evaluate(attrs("Recife", 1600000, 10.0, "city"));
    EXPECT_TRUE(s.visible);
    EXPECT_TRUE(s.label.empty());
    EXPECT_FALSE(s.extrudeM);
    EXPECT_EQ(s.widthPx, FeatureStyle{}.widthPx);
}

TEST(VectorStyle, RulesApplyInOrderOverTheDefaults) {
    auto style = styleFrom(R"J({
        "color": "#ff8000", "width": 3, "label": "{name} ({pop})",
        "rules": [
            {"name": "big", "when": {"pop": {"min": 1000000}}, "width": 6, "iconSize": 24},
            {"when": {"kind": ["town", "village"]}, "color": [0, 0, 1], "label": "{name}"},
            {"name": "hidden", "when": {"name": "Atlantis"}, "visible": false}
        ]})J");
    ASSERT_TRUE(style) << style.message();
    ASSERT_EQ(style->ruleCount(), 3u);
    EXPECT_EQ(style->ruleName(0), "big");
    EXPECT_EQ(style->ruleName(1), "rule 2");

    FeatureStyle s = style->evaluate(attrs("Recife", 1600000, 10.0, "city"));
    EXPECT_EQ(s.color, glm::dvec3(1.0, 128.0 / 255.0, 0.0));
    EXPECT_EQ(s.widthPx, 6.0);
    EXPECT_EQ(s.iconSizePx, 24.0);
    EXPECT_EQ(s.label, "Recife (1600000)");

    s = style->evaluate(attrs("Olinda", 390000, 5.0, "town"));
    EXPECT_EQ(s.widthPx, 3.0);   // below the range
    EXPECT_EQ(s.color, glm::dvec3(0, 0, 1));
    EXPECT_EQ(s.label, "Olinda");

    EXPECT_FALSE(style->evaluate(attrs("Atlantis", 0, 0.0, "city")).visible);
    // A rule switched off (a live setting) no longer applies.
    style->setRuleEnabled(2, false);
    EXPECT_TRUE(style->evaluate(attrs("Atlantis", 0, 0.0, "city")).visible);
}

TEST(VectorStyle, ARuleForOneLayerIsBoundAndAppliedOnlyThere) {
    // A source with several layers: a rule names a field only its own layer has.
    static json keep;
    keep = json::parse(R"J({"width": 1, "rules": [
        {"layer": "roads", "when": {"lanes": {"min": 4}}, "width": 5},
        {"layer": "cities", "when": {"kind": "city"}, "width": 3, "enabled": false}]})J");
    auto read = VectorStyle::read(&keep, "scene.json", "/layers/1/style");
    ASSERT_TRUE(read) << read.message();
    EXPECT_FALSE(read->ruleEnabled(1));   // "enabled": false, as saved
    VectorStyle cities = *read, roads = *read;
    ASSERT_TRUE(cities.bind(kFields, "cities"));   // no "lanes" here: that rule is not for this layer
    EXPECT_EQ(cities.evaluate(attrs("Recife", 1, 0.0, "city")).widthPx, 1.0);
    cities.setRuleEnabled(1, true);
    EXPECT_EQ(cities.evaluate(attrs("Recife", 1, 0.0, "city")).widthPx, 3.0);
    const std::vector<FieldInfo> roadFields = {{"lanes", "Integer"}};
    ASSERT_TRUE(roads.bind(roadFields, "roads"));
    EXPECT_EQ(roads.evaluate(std::vector<AttributeValue>{AttributeValue{int64_t(6)}}).widthPx, 5.0);
    EXPECT_EQ(roads.evaluate(std::vector<AttributeValue>{AttributeValue{int64_t(2)}}).widthPx, 1.0);
    // On its own layer, a field that is missing is still an error naming the rule.
    VectorStyle wrong = *read;
    auto bound = wrong.bind(kFields, "roads");
    ASSERT_FALSE(bound);
    EXPECT_NE(bound.message().find("/layers/1/style/rules/0/when/lanes"), std::string::npos) << bound.message();
}

TEST(VectorStyle, RangesIncludeTheirMinAndExcludeTheirMaxAndSkipNonNumbers) {
    auto style = styleFrom(R"J({"rules": [{"when": {"height": {"min": 10, "max": 20}}, "visible": false}]})J");
    ASSERT_TRUE(style) << style.message();
    EXPECT_TRUE(style->evaluate(attrs("a", 0, 9.999, "x")).visible);
    EXPECT_FALSE(style->evaluate(attrs("a", 0, 10.0, "x")).visible);
    EXPECT_FALSE(style->evaluate(attrs("a", 0, int64_t(19), "x")).visible);
    EXPECT_TRUE(style->evaluate(attrs("a", 0, 20.0, "x")).visible);
    EXPECT_TRUE(style->evaluate(attrs("a", 0, AttributeValue{}, "x")).visible);            // null
    EXPECT_TRUE(style->evaluate(attrs("a", 0, AttributeValue{"15"}, "x")).visible);        // text
}

TEST(VectorStyle, EqualityComparesNumbersByValueAndNullOnlyWithNull) {
    auto style = styleFrom(R"J({"rules": [{"when": {"pop": 5, "height": null}, "visible": false}]})J");
    ASSERT_TRUE(style) << style.message();
    EXPECT_FALSE(style->evaluate(attrs("a", 5, AttributeValue{}, "x")).visible);
    EXPECT_TRUE(style->evaluate(attrs("a", 5, 0.0, "x")).visible);   // both conditions must hold
    EXPECT_TRUE(style->evaluate(attrs("a", 6, AttributeValue{}, "x")).visible);
}

TEST(VectorStyle, ExtrusionByConstantFieldOrScaledField) {
    auto constant = styleFrom(R"J({"extrude": 30})J");
    ASSERT_TRUE(constant);
    EXPECT_EQ(constant->evaluate(attrs("a", 0, 5.0, "x")).extrudeM, 30.0);
    auto field = styleFrom(R"J({"extrude": "height"})J");
    ASSERT_TRUE(field);
    EXPECT_EQ(field->evaluate(attrs("a", 0, 12.5, "x")).extrudeM, 12.5);
    EXPECT_FALSE(field->evaluate(attrs("a", 0, AttributeValue{}, "x")).extrudeM);   // no height: flat
    auto scaled = styleFrom(R"J({"extrude": {"field": "pop", "scale": 3, "add": 1},
                               "rules": [{"when": {"kind": "park"}, "extrude": null}]})J");
    ASSERT_TRUE(scaled) << scaled.message();
    EXPECT_EQ(scaled->evaluate(attrs("a", 4, 0.0, "house")).extrudeM, 13.0);
    EXPECT_FALSE(scaled->evaluate(attrs("a", 4, 0.0, "park")).extrudeM);
}

TEST(VectorStyle, LabelTemplatesFormatValuesAndEscapeBraces) {
    auto style = styleFrom(R"J({"label": "{{{name}}}: {height} m, {pop}"})J");
    ASSERT_TRUE(style) << style.message();
    EXPECT_EQ(style->evaluate(attrs("Pico", 7, 2351.123456789, "x")).label, "{Pico}: 2351.12 m, 7");
    EXPECT_EQ(style->evaluate(attrs("Pico", 7, AttributeValue{}, "x")).label, "{Pico}:  m, 7");
}

TEST(VectorStyle, ErrorsNameTheFileTheKeyAndTheProblem) {
    const auto message = [](const std::string& text) {
        auto s = styleFrom(text);
        return s ? std::string("(no error)") : s.message();
    };
    EXPECT_EQ(message(R"J({"rules": [{"when": {"popp": 5}}]})J"),
              "scene.json: /layers/1/style/rules/0/when/popp: layer 'cities' has no field 'popp' (its fields: name, pop, height, kind)");
    EXPECT_EQ(message(R"J({"label": "{nme}"})J"),
              "scene.json: /layers/1/style/label: layer 'cities' has no field 'nme' (its fields: name, pop, height, kind)");
    EXPECT_EQ(message(R"J({"extrude": "levels"})J"),
              "scene.json: /layers/1/style/extrude: layer 'cities' has no field 'levels' (its fields: name, pop, height, kind)");
    EXPECT_NE(message(R"J({"colour": [1, 0, 0]})J").find("/layers/1/style/colour"), std::string::npos);   // unknown key
    EXPECT_NE(message(R"J({"color": "red"})J").find("\"#rrggbb\""), std::string::npos);
    EXPECT_NE(message(R"J({"color": [1, 2, 0]})J").find("from 0 to 1"), std::string::npos);
    EXPECT_NE(message(R"J({"opacity": 2})J").find("/layers/1/style/opacity"), std::string::npos);
    EXPECT_NE(message(R"J({"label": "{name"})J").find("without a field name"), std::string::npos);
    EXPECT_NE(message(R"J({"label": "a}b"})J").find("'}' without its '{'"), std::string::npos);
    EXPECT_NE(message(R"J({"rules": [{"when": {"pop": {"min": 5, "max": 1}}}]})J").find("min is above its max"), std::string::npos);
    EXPECT_NE(message(R"J({"rules": [{"when": {"pop": {}}}]})J").find("\"min\", \"max\" or both"), std::string::npos);
    EXPECT_NE(message(R"J({"rules": {"when": {}}})J").find("/layers/1/style/rules: expected an array"), std::string::npos);
    EXPECT_NE(message(R"J({"rules": [{"name": "x", "colr": [0, 0, 0]}]})J").find("/layers/1/style/rules/0/colr"), std::string::npos);
    EXPECT_NE(message(R"J({"minRange": 10, "maxRange": 5})J").find("minRange is above maxRange"), std::string::npos);
    EXPECT_NE(message(R"J({"extrude": -3})J").find("0 or more"), std::string::npos);
    EXPECT_NE(message(R"J([1, 2])J").find("expected an object"), std::string::npos);
    EXPECT_NE(message(R"J({"dash": [4]})J").find("/layers/1/style/dash: expected [on, off]"), std::string::npos);
    EXPECT_NE(message(R"J({"dash": [4, 0]})J").find("both lengths above 0"), std::string::npos);
    EXPECT_NE(message(R"J({"dash": "--"})J").find("/layers/1/style/dash"), std::string::npos);
}

TEST(VectorStyle, IconsScaleWithTheCameraRangeBetweenNearAndFar) {
    auto style = styleFrom(R"J({"iconSize": 20, "iconScale": {"near": 1000, "far": 11000, "scale": 0.5}})J");
    ASSERT_TRUE(style) << style.message();
    const FeatureStyle s = style->evaluate(attrs("A", 1, 1.0, "city"));
    EXPECT_DOUBLE_EQ(s.iconSizeAt(0.0), 20.0);
    EXPECT_DOUBLE_EQ(s.iconSizeAt(1000.0), 20.0);
    EXPECT_DOUBLE_EQ(s.iconSizeAt(6000.0), 15.0);
    EXPECT_DOUBLE_EQ(s.iconSizeAt(1e7), 10.0);
    EXPECT_DOUBLE_EQ(FeatureStyle{}.iconSizeAt(1e7), FeatureStyle{}.iconSizePx) << "no scale: constant";
    auto bad = styleFrom(R"J({"iconScale": {"near": 5, "far": 1, "scale": 1}})J");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find("/layers/1/style/iconScale/far: far must be beyond near"), std::string::npos) << bad.message();
    auto missing = styleFrom(R"J({"iconScale": {"near": 5}})J");
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.message().find("/layers/1/style/iconScale/far"), std::string::npos) << missing.message();
}

TEST(VectorStyle, DashesAsAPairOrOneLengthAndSolidByRule) {
    auto style = styleFrom(R"J({"dash": [8, 3], "rules": [{"when": {"kind": "town"}, "dash": 5}, {"when": {"kind": "road"}, "dash": null}]})J");
    ASSERT_TRUE(style) << style.message();
    EXPECT_EQ(style->evaluate(attrs("A", 1, 1.0, "city")).dashPx, glm::dvec2(8.0, 3.0));
    EXPECT_EQ(style->evaluate(attrs("B", 1, 1.0, "town")).dashPx, glm::dvec2(5.0, 5.0));
    EXPECT_EQ(style->evaluate(attrs("C", 1, 1.0, "road")).dashPx, glm::dvec2(0.0));
}

TEST(VectorStyle, AttributeTextOfEachType) {
    EXPECT_EQ(attributeText(AttributeValue{}), "");
    EXPECT_EQ(attributeText(AttributeValue{int64_t(-42)}), "-42");
    EXPECT_EQ(attributeText(AttributeValue{0.1 + 0.2}), "0.3");
    EXPECT_EQ(attributeText(AttributeValue{1e20}), "1e+20");
    EXPECT_EQ(attributeText(AttributeValue{std::string("São Paulo")}), "São Paulo");
}

}  // namespace
}  // namespace orbis::vector

namespace orbis::vector {
namespace {

TEST(VectorStyle, AKmlKeepsItsOwnStylesUnlessTheSceneNamesTheProperty) {
    // Shared and inline KML styles, read through OGR (LIBKML), then styled with and without the
    // scene's word.
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("orbis-kml-style-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::filesystem::path kml = dir / "styled.kml";
    std::ofstream(kml) << R"KML(<?xml version="1.0" encoding="UTF-8"?>
<kml xmlns="http://www.opengis.net/kml/2.2"><Document>
  <Style id="red"><LineStyle><color>ff0000ff</color><width>4</width></LineStyle>
    <PolyStyle><color>7f00ff00</color></PolyStyle>
    <IconStyle><scale>1.5</scale><Icon><href>pin.png</href></Icon></IconStyle>
    <LabelStyle><color>ffffff00</color><scale>2</scale></LabelStyle></Style>
  <Placemark><name>A</name><styleUrl>#red</styleUrl><Point><coordinates>9,46,0</coordinates></Point></Placemark>
  <Placemark><name>B</name><Style><LineStyle><color>ff00ff00</color><width>2</width></LineStyle></Style>
    <LineString><coordinates>9,46,0 9.1,46.1,0</coordinates></LineString></Placemark>
  <Placemark><name>C</name><Polygon><outerBoundaryIs><LinearRing><coordinates>9,46 9.1,46 9.1,46.1 9,46</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark>
</Document></kml>)KML";
    VectorReadOptions options;
    options.source = kml.string();
    auto data = readVector(options);
    std::filesystem::remove_all(dir);
    ASSERT_TRUE(data) << data.message();
    const VectorLayer& layer = data->layers.at(0);
    ASSERT_EQ(layer.features.size(), 3u);
    ASSERT_EQ(layer.styles.size(), 2u);
    const auto ownStyle = [&](size_t i) { return layer.features[i].style < 0 ? nullptr : &layer.styles[size_t(layer.features[i].style)]; };
    ASSERT_TRUE(ownStyle(0) && ownStyle(1));
    EXPECT_EQ(ownStyle(2), nullptr);

    auto plain = VectorStyle::read(nullptr, "scene.json", "/layers/0/style");
    ASSERT_TRUE(plain && plain->bind(layer.fields, layer.name));
    const FeatureStyle a = plain->evaluate(layer.features[0].attributes, ownStyle(0));
    EXPECT_EQ(a.color, glm::dvec3(1, 0, 0));   // KML's aabbggrr
    EXPECT_EQ(a.widthPx, 4.0);
    EXPECT_EQ(a.fill, glm::dvec3(0, 1, 0));
    EXPECT_NEAR(a.fillOpacity, 127.0 / 255.0, 1e-12);
    EXPECT_EQ(a.icon, "pin.png");
    EXPECT_DOUBLE_EQ(a.iconSizePx, 1.5 * FeatureStyle{}.iconSizePx);
    EXPECT_EQ(a.labelColor, glm::dvec3(0, 1, 1));
    EXPECT_DOUBLE_EQ(a.labelSizePx, 2.0 * FeatureStyle{}.labelSizePx);
    EXPECT_EQ(plain->evaluate(layer.features[1].attributes, ownStyle(1)).color, glm::dvec3(0, 1, 0));
    EXPECT_EQ(plain->evaluate(layer.features[2].attributes, ownStyle(2)).color, FeatureStyle{}.color);

    // The scene names the width and, for B, the colour: the rest stays the file's.
    json scene = json::parse(R"({"width": 7, "rules": [{"when": {"Name": "B"}, "color": [0, 0, 1]}]})");
    auto overridden = VectorStyle::read(&scene, "scene.json", "/layers/0/style");
    ASSERT_TRUE(overridden) << overridden.message();
    ASSERT_TRUE(overridden->bind(layer.fields, layer.name));
    const FeatureStyle a2 = overridden->evaluate(layer.features[0].attributes, ownStyle(0));
    EXPECT_EQ(a2.widthPx, 7.0);
    EXPECT_EQ(a2.color, glm::dvec3(1, 0, 0));
    EXPECT_EQ(overridden->evaluate(layer.features[1].attributes, ownStyle(1)).color, glm::dvec3(0, 0, 1));
}

TEST(VectorStyle, ItsWidestReachFarthestRangeAndExtrusionAreKnownWithoutData) {
    auto plain = styleFrom(R"({"width": 2})");
    ASSERT_TRUE(plain) << plain.message();
    EXPECT_FALSE(plain->namesExtrusion());
    EXPECT_TRUE(std::isinf(plain->maxRangeM()));
    const double base = plain->reachPx();
    EXPECT_GE(base, 0.5 * FeatureStyle{}.iconSizePx);
    // A rule with a wide line or an icon reaches farther; ranges: the farthest any rule allows.
    auto wide = styleFrom(R"({"maxRange": 1e6, "rules": [{"when": {"kind": "road"}, "width": 40, "maxRange": 3e6},)"
                          R"( {"when": {"kind": "hut"}, "icon": "hut.png", "iconSize": 20, "extrude": {"field": "height"}}]})");
    ASSERT_TRUE(wide) << wide.message();
    EXPECT_GE(wide->reachPx(), 0.5 * 20 * 4);   // an icon may be 4:1 wide
    EXPECT_EQ(wide->maxRangeM(), 3e6);
    EXPECT_TRUE(wide->namesExtrusion());
    wide->setRuleEnabled(0, false);
    EXPECT_EQ(wide->maxRangeM(), 1e6);
}

}  // namespace
}  // namespace orbis::vector
