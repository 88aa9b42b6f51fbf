// The volume layer on lavapipe with validation: direct volume rendering of synthetic fields in
// a curved box, rays that end at the scene depth, and the stiff cases (no data, a constant
// field, a box across the antimeridian and at a pole, the camera inside, 1 and 4096 steps).
#include "engine/gpu/Device.h"
#include "layers/volume/VolumeLayer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/GpuTest.h"

#include <cmath>

namespace orbis::test {
namespace {

std::string volumeScene(const std::string& viewpoint, const std::string& volume, bool withGlobe = true) {
    return R"({"viewpoint": )" + viewpoint +
           R"(, "time": {"start": "2026-06-21T12:00:00Z", "end": "2026-06-21T12:00:00Z"}, "layers": [)" +
           (withGlobe ? std::string(R"({"type": "globe", "name": "Earth", "sky": false})") : std::string()) +
           (withGlobe && !volume.empty() ? ", " : "") + volume + "]}";
}

std::string sphereVolume(const std::string& extra = "", const std::string& box = "") {
    return R"({"type": "volume", "name": "Sphere", "synthetic": {"field": "sphere", "size": [48, 48, 48])" +
           (box.empty() ? std::string(R"(, "lon": [-10, 10], "lat": [40, 60], "height": [0, 800000])") : box) +
           R"(}, "colorMap": "viridis", "opacity": [[0, 0.6], [16, 0.3], [24, 0.0]])" + extra + "}";
}

const char* kOblique = R"({"lon": 0, "lat": 50, "height": 100000, "pitch": -35, "range": 4500000})";

class VolumeRender : public GpuTest {
protected:
    std::unique_ptr<scene::Scene> load(const std::string& json) {
        scene::LayerRegistry registry;
        layers::registerBuiltinLayers(registry);
        return buildScene(json, registry);
    }
    ImageRgba8 render(const std::string& json, uint32_t w = 320, uint32_t h = 240) {
        auto scene = load(json);
        if (!scene) return {};
        render::Renderer renderer(device(), w, h);
        return renderOnce(renderer, *scene);
    }
};

size_t differing(const ImageRgba8& a, const ImageRgba8& b, int tolerance = 2) {
    return a.pixels.size() == b.pixels.size() ? countDifferentPixels(a, b, tolerance) : size_t(-1);
}

TEST_F(VolumeRender, SphereFieldDvrMatchesGolden) {
    const auto img = render(volumeScene(kOblique, sphereVolume()));
    ASSERT_FALSE(img.pixels.empty());
    EXPECT_TRUE(matchesGolden(img, "volume_sphere_dvr"));
    // The volume shows: the image differs from the globe alone over a good part of the box.
    const auto globeOnly = render(volumeScene(kOblique, ""));
    EXPECT_GT(differing(img, globeOnly), size_t(img.width * img.height / 20));
}

TEST_F(VolumeRender, RaysEndAtTheSceneDepth) {
    // A box on the far side of the Earth: the globe hides all of it.
    const std::string hidden = sphereVolume("", R"(, "lon": [170, 190], "lat": [-60, -40], "height": [0, 800000])");
    const auto globeOnly = render(volumeScene(kOblique, ""));
    EXPECT_EQ(differing(render(volumeScene(kOblique, hidden)), globeOnly, 0), 0u);
    // A constant fog reaching 300 km underground looks like one that stops at the ground when
    // the globe is drawn (the rays end at its depth), and denser without it.
    const auto fog = [](const char* bottom) {
        return std::string(R"({"type": "volume", "name": "Fog", "synthetic": {"field": "constant", "size": [8, 8, 8], )") +
               R"("lon": [-10, 10], "lat": [40, 60], "height": [)" + bottom +
               R"(, 800000]}, "range": [0, 2], "opacity": [[0, 0.05], [2, 0.05]], "steps": 400})";
    };
    const auto aboveGround = render(volumeScene(kOblique, fog("0")));
    const auto reachingDown = render(volumeScene(kOblique, fog("-300000")));
    const auto reachingDownNoGlobe = render(volumeScene(kOblique, fog("-300000"), false));
    const auto aboveGroundNoGlobe = render(volumeScene(kOblique, fog("0"), false));
    const size_t n = size_t(aboveGround.width) * aboveGround.height;
    EXPECT_LT(differing(aboveGround, reachingDown, 3), n / 100);
    EXPECT_GT(differing(aboveGroundNoGlobe, reachingDownNoGlobe, 3), n / 50);
}

TEST_F(VolumeRender, EmptyAndConstantFieldsGiveCleanImages) {
    const auto globeOnly = render(volumeScene(kOblique, ""));
    // All no data: transparent everywhere.
    const auto empty = render(volumeScene(
        kOblique, R"({"type": "volume", "name": "E", "synthetic": {"field": "empty", "size": [8, 8, 8], "lon": [-10, 10], "lat": [40, 60], "height": [0, 800000]}})"));
    EXPECT_EQ(differing(empty, globeOnly, 0), 0u);
    // Constant: a uniform fog, no NaN (a NaN pixel would read back as black or garbage).
    const auto constant = render(volumeScene(
        kOblique, R"({"type": "volume", "name": "C", "synthetic": {"field": "constant", "size": [8, 8, 8], "lon": [-10, 10], "lat": [40, 60], "height": [0, 800000]}, "range": [0, 2], "opacity": [[0, 0.2], [2, 0.2]]})"));
    EXPECT_GT(differing(constant, globeOnly), 100u);
}

TEST_F(VolumeRender, StiffBoxesAndStepCounts) {
    // Across the antimeridian and up to the pole, seen from above the pole; the camera inside
    // a box; 1 and 4096 steps. Each must render (validation on) and show the volume.
    const std::string polar = sphereVolume("", R"(, "lon": [150, 210], "lat": [70, 90], "height": [0, 500000])");
    const char* abovePole = R"({"lon": 180, "lat": 90, "range": 6000000})";
    const auto globeAbove = render(volumeScene(abovePole, ""));
    const auto polarImg = render(volumeScene(abovePole, polar));
    EXPECT_TRUE(matchesGolden(polarImg, "volume_polar_antimeridian"));
    EXPECT_GT(differing(polarImg, globeAbove), 500u);

    const char* inside = R"({"lon": 0, "lat": 50, "height": 400000, "pitch": -10, "range": 1})";
    const auto insideImg = render(volumeScene(inside, sphereVolume()));
    const auto insideGlobe = render(volumeScene(inside, ""));
    EXPECT_GT(differing(insideImg, insideGlobe), size_t(insideImg.width * insideImg.height / 4));

    for (int steps : {1, 4096}) {
        const auto img = render(volumeScene(kOblique, sphereVolume(", \"steps\": " + std::to_string(steps))));
        ASSERT_FALSE(img.pixels.empty()) << steps;
        EXPECT_GT(differing(img, render(volumeScene(kOblique, ""))), 50u) << steps;
    }
}

TEST_F(VolumeRender, MoreStepsConvergeToTheReference) {
    // Error against the 1600-step image falls as the step count grows.
    const auto reference = render(volumeScene(kOblique, sphereVolume(R"(, "steps": 1600)")));
    double last = 1e9;
    for (int steps : {25, 100, 400}) {
        const auto img = render(volumeScene(kOblique, sphereVolume(", \"steps\": " + std::to_string(steps))));
        double sum = 0.0;
        for (size_t i = 0; i < img.pixels.size(); ++i) {
            const double d = double(img.pixels[i]) - double(reference.pixels[i]);
            sum += d * d;
        }
        const double rmse = std::sqrt(sum / double(img.pixels.size()));
        EXPECT_LT(rmse, last) << steps;
        last = rmse;
    }
    EXPECT_LT(last, 2.0);
}

TEST_F(VolumeRender, IsosurfacesMatchGoldenAndSurviveStiffValues) {
    const std::string iso = R"({"type": "volume", "name": "Shells", "synthetic": {"field": "sphere", "size": [48, 48, 48], )"
                            R"("lon": [-10, 10], "lat": [40, 60], "height": [0, 800000]}, "mode": ["iso"], )"
                            R"("isovalues": [12, 20], "isoOpacity": 0.6, "colorMap": "viridis", "range": [0, 24]})";
    const auto img = render(volumeScene(kOblique, iso));
    EXPECT_TRUE(matchesGolden(img, "volume_sphere_iso"));
    const auto globeOnly = render(volumeScene(kOblique, ""));
    EXPECT_GT(differing(img, globeOnly), size_t(img.width * img.height / 20));
    // Both modes at once draw more than either.
    std::string both = iso;
    both.replace(both.find(R"("mode": ["iso"])"), 15, R"("mode": ["iso", "dvr"])");
    EXPECT_GT(differing(render(volumeScene(kOblique, both)), img), 100u);

    // An isovalue on grid values exactly (the sphere field is integer along the axes through
    // its centre), a constant field whose every value is the isovalue (no crossing, no NaN
    // normals), one step and 4096 steps: all render cleanly.
    const auto exact = render(volumeScene(kOblique, std::string(iso).replace(iso.find("[12, 20]"), 8, "[10]")));
    EXPECT_GT(differing(exact, globeOnly), 100u);
    const auto constant = render(volumeScene(
        kOblique, R"({"type": "volume", "name": "C", "synthetic": {"field": "constant", "size": [8, 8, 8], "lon": [-10, 10], "lat": [40, 60], "height": [0, 800000]}, "mode": ["iso"], "isovalues": [1]})"));
    EXPECT_EQ(differing(constant, globeOnly, 0), 0u);
    for (const char* steps : {"1", "4096"}) {
        std::string s = iso;
        s.insert(s.size() - 1, std::string(R"(, "steps": )") + steps);
        ASSERT_FALSE(render(volumeScene(kOblique, s)).pixels.empty()) << steps;
    }
}

TEST(VolumeSettings, BadScenesNameTheKeyAndTheProblem) {
    scene::LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    const auto build = [&](const std::string& layer) -> std::string {
        auto desc = scene::parseSceneText(R"({"layers": [)" + layer + "]}", "bad.json", ".");
        if (!desc) return desc.message();
        auto scene = scene::Scene::build(std::move(desc).value(), registry);
        return scene ? std::string() : scene.message();
    };
    const struct { const char* layer; const char* expect; } cases[] = {
        {R"({"type": "volume"})", "give the data"},
        {R"({"type": "volume", "path": "missing.nc", "variable": "t"})", "missing.nc: no such file"},
        {R"({"type": "volume", "path": "x.nc"})", "/layers/0/variable: name the variable"},
        {R"({"type": "volume", "synthetic": {"field": "cube"}})", "expected \"sphere\""},
        {R"({"type": "volume", "synthetic": {}, "mode": ["slice"]})", "\"slice\" is not implemented yet"},
        {R"({"type": "volume", "synthetic": {}, "mode": ["iso"]})", "/layers/0/isovalues: missing"},
        {R"({"type": "volume", "synthetic": {}, "mode": ["iso"], "isovalues": []})", "needs 1 to 8 isovalues"},
        {R"({"type": "volume", "synthetic": {}, "isovalues": [1]})", "only used with mode \"iso\""},
        {R"({"type": "volume", "synthetic": {}, "mode": []})", "name at least one mode"},
        {R"({"type": "volume", "synthetic": {}, "steps": 0})", "/layers/0/steps"},
        {R"({"type": "volume", "synthetic": {}, "colorMap": "jet"})", "unknown colour map \"jet\""},
        {R"({"type": "volume", "synthetic": {}, "range": [5, 1]})", "low < high"},
        {R"({"type": "volume", "synthetic": {}, "opacity": [[0, 2]]})", "alpha in 0..1"},
        {R"({"type": "volume", "synthetic": {"lat": [80, 100]}})", "/layers/0/synthetic/lat"},
    };
    for (const auto& c : cases) {
        const std::string message = build(c.layer);
        EXPECT_NE(message.find(c.expect), std::string::npos) << c.layer << " -> " << message;
    }
    EXPECT_EQ(build(R"({"type": "volume", "synthetic": {"size": [4, 4, 4]}})"), "");
}

}  // namespace
}  // namespace orbis::test
