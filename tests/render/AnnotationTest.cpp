// Annotation pins: which pins show (the ground and the horizon hide them, the nearest win the
// budget), the scene builds their layer only when it has pins, the pins render (golden) and
// they are saved with the scene.
#include "engine/gpu/Device.h"
#include "engine/scene/SceneSave.h"
#include "globe/Ellipsoid.h"
#include "globe/Viewpoint.h"
#include "layers/annotations/PinOverlay.h"
#include "tests/render/RenderHelpers.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/GpuTest.h"

#include <cmath>

namespace orbis::test {
namespace {

using layers::layoutPins;
using layers::pinHidden;
using layers::PinStyle;
using scene::Annotation;

const auto& wgs84 = globe::Ellipsoid::wgs84();

glm::dvec3 at(double lon, double lat, double h) { return wgs84.toEcef({lon, lat, h}); }

scene::Camera cameraAt(double lon, double lat, double range, double pitch = -90.0) {
    scene::Camera c;
    globe::Viewpoint vp;
    vp.lonDeg = lon;
    vp.latDeg = lat;
    vp.pitchDeg = pitch;
    vp.range = range;
    c.setPose(globe::poseFromViewpoint(vp));
    return c;
}

TEST(PinOverlay, GroundBetweenHidesAPin) {
    const glm::dvec3 eye = at(10.0, 45.0, 500.0);
    const glm::dvec3 pin = at(10.1, 45.0, 0.0);   // ~7.9 km east, on the ground
    const scene::GroundHeightFn flat = [](double, double) { return std::optional<double>(0.0); };
    EXPECT_FALSE(pinHidden(eye, pin, flat)) << "flat ground: the pin is in sight";
    // A 2 km ridge half-way along the line of sight.
    const scene::GroundHeightFn ridge = [](double lon, double) {
        return std::optional<double>(std::abs(lon - 10.05) < 0.01 ? 2000.0 : 0.0);
    };
    EXPECT_TRUE(pinHidden(eye, pin, ridge));
    // The ground rising to the pin's own height just before it does not hide it.
    const scene::GroundHeightFn slope = [](double lon, double) { return std::optional<double>((lon - 10.0) / 0.1 * 300.0); };
    EXPECT_FALSE(pinHidden(eye, at(10.1, 45.0, 300.0), slope));
    // No ground known: the ellipsoid; the far side of the Earth is below the horizon.
    EXPECT_TRUE(pinHidden(at(0.0, 0.0, 1e7), at(180.0, 0.0, 0.0), nullptr));
    EXPECT_FALSE(pinHidden(at(0.0, 0.0, 1e7), at(0.0, 0.0, 0.0), nullptr));
    // Degenerate: the eye at the pin.
    EXPECT_FALSE(pinHidden(pin, pin, flat));
}

TEST(PinOverlay, PinsBehindOrOffScreenAreLeftOut) {
    const scene::Camera camera = cameraAt(0.0, 0.0, 1e6);
    const std::vector<Annotation> pins = {{"centre", 0.0, 0.0, 0.0},
                                          {"far side", 180.0, 0.0, 0.0},
                                          {"off screen", 60.0, 0.0, 0.0},
                                          {"bad", std::nan(""), 0.0, 0.0}};
    const auto layout = layoutPins(pins, camera, 640, 480, nullptr, PinStyle{}, 100000);
    EXPECT_EQ(layout.drawn, 1u);
    EXPECT_EQ(layout.dropped, 0u);
    ASSERT_FALSE(layout.quads.empty());
    // The stem's foot is the pin's point: the centre of the view.
    bool stemAtCentre = false;
    for (const auto& q : layout.quads)
        if (q.min.x <= 320.0 && q.max.x >= 320.0 && q.max.y >= 239.0 && q.max.y <= 242.0) stemAtCentre = true;
    EXPECT_TRUE(stemAtCentre);
    for (const auto& q : layout.quads) {
        ASSERT_TRUE(std::isfinite(q.min.x) && std::isfinite(q.max.y));
        EXPECT_LE(q.min.x, q.max.x);
        EXPECT_LE(q.min.y, q.max.y);
    }
}

TEST(PinOverlay, NearestPinsWinTheBudgetAndAreDrawnOnTop) {
    const scene::Camera camera = cameraAt(0.0, 0.0, 2e6, -60.0);
    std::vector<Annotation> pins;
    for (int i = 0; i < 50; ++i) pins.push_back({"pin " + std::to_string(i), 0.0, -6.0 + 0.2 * i, 0.0});
    PinStyle noLabels;
    noLabels.labels = false;   // 4 rectangles a pin
    const auto all = layoutPins(pins, camera, 800, 600, nullptr, noLabels, 100000);
    ASSERT_GT(all.drawn, 10u);
    const auto some = layoutPins(pins, camera, 800, 600, nullptr, noLabels, 4 * 5);
    EXPECT_EQ(some.drawn, 5u);
    EXPECT_EQ(some.dropped, all.drawn - 5);
    EXPECT_EQ(some.quads.size(), 20u);
    // The last pin drawn (on top) is the nearest: lowest on the screen, looking north and down.
    EXPECT_GE(some.quads.back().max.y, some.quads.front().max.y);
    // Labels count against the budget too, and never exceed it.
    const auto labelled = layoutPins(pins, camera, 800, 600, nullptr, PinStyle{}, 300);
    EXPECT_LE(labelled.quads.size(), 300u);
    EXPECT_GT(labelled.drawn, 0u);
}

class AnnotationRender : public GpuTest {};

const char* kPinScene = R"({
  "viewpoint": {"lon": 20, "lat": 20, "range": 16000000},
  "time": {"start": "2026-03-20T12:00:00Z", "end": "2026-03-20T12:00:00Z"},
  "annotations": [{"name": "Summit", "lon": 10, "lat": 46, "height": 3000},
                  {"name": "Cape Town", "lon": 18.4, "lat": -33.9},
                  {"name": "Far side", "lon": -170, "lat": 0}],
  "layers": [{"type": "globe", "name": "Earth"}]})";

TEST_F(AnnotationRender, PinsMatchGolden) {
    scene::LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    auto scene = buildScene(kPinScene, registry);
    ASSERT_TRUE(scene);
    ASSERT_EQ(scene->resources().size(), 2u) << "the pins' layer joins the scene";
    EXPECT_EQ(scene->resources().back().type, "annotations");
    render::Renderer renderer(device(), 480, 270);
    const ImageRgba8 img = renderOnce(renderer, *scene);
    EXPECT_TRUE(matchesGolden(img, "annotations_pins"));
    EXPECT_EQ(scene->resources().back().layer->asStats()->itemsDrawn(), 2u) << "the far side's pin is hidden";

    // Hidden, the pins leave the globe alone.
    scene->resources().back().visible = false;
    const ImageRgba8 without = renderOnce(renderer, *scene);
    EXPECT_GT(countDifferentPixels(img, without, 8), size_t(400));
    auto plain = buildScene(globeScene(R"({"lon": 20, "lat": 20, "range": 16000000})"), registry);
    EXPECT_LT(countDifferentPixels(without, renderOnce(renderer, *plain), 2), size_t(10));
}

TEST_F(AnnotationRender, OnlyScenesWithPinsBuildTheirLayer) {
    scene::LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    auto plain = buildScene(globeScene(R"({"lon": 0, "lat": 0, "range": 2e7})"), registry);
    ASSERT_TRUE(plain);
    EXPECT_EQ(registry.constructed("annotations"), 0);
    EXPECT_EQ(plain->resources().size(), 1u);
    // The viewer places the first pin: the layer comes then, once.
    plain->annotations().push_back({"Here", 0.0, 0.0, 0.0});
    ASSERT_TRUE(plain->ensureAnnotationLayer(registry).ok());
    ASSERT_TRUE(plain->ensureAnnotationLayer(registry).ok());
    EXPECT_EQ(registry.constructed("annotations"), 1);
    EXPECT_EQ(plain->resources().size(), 2u);
}

TEST_F(AnnotationRender, EditedPinsAreSavedAndRenderAgain) {
    scene::LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    auto scene = buildScene(kPinScene, registry);
    ASSERT_TRUE(scene);
    scene->annotations().erase(scene->annotations().begin());   // "Summit" deleted
    scene->annotations().push_back({"Nairobi", 36.8, -1.3, 1700.0});
    const nlohmann::json saved = scene::sceneToJson(*scene, "saved.json");
    ASSERT_EQ(saved["annotations"].size(), 3u);
    EXPECT_EQ(saved["annotations"][0]["name"], "Cape Town");
    EXPECT_EQ(saved["annotations"][2]["name"], "Nairobi");
    EXPECT_EQ(saved["annotations"][2]["height"], 1700.0);
    EXPECT_EQ(saved["layers"].size(), 1u) << "the pins' layer is not a layer of the file";

    render::Renderer renderer(device(), 480, 270);
    const ImageRgba8 before = renderOnce(renderer, *scene);
    auto again = buildScene(saved.dump(), registry);
    ASSERT_TRUE(again);
    EXPECT_LT(countDifferentPixels(before, renderOnce(renderer, *again), 8), size_t(200));
}

}  // namespace
}  // namespace orbis::test
