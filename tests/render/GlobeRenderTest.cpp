// Golden images of the minimal globe layer, and the stiff cases: poles, antimeridian, a camera
// 1 m above the ground and one 40 000 km out.
#include "engine/gpu/Device.h"
#include "globe/Ellipsoid.h"
#include "tests/render/RenderHelpers.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/GpuTest.h"

namespace orbis::test {
namespace {

class GlobeRender : public GpuTest {
protected:
    ImageRgba8 render(const std::string& json, uint32_t w = 320, uint32_t h = 240) {
        scene::LayerRegistry registry;
        layers::registerBuiltinLayers(registry);
        auto scene = buildScene(json, registry);
        if (!scene) return {};
        render::Renderer renderer(device(), w, h);
        return renderOnce(renderer, *scene);
    }
};

// Fraction of pixels that are not the (near-black) background.
double coverage(const ImageRgba8& img) {
    size_t lit = 0;
    for (size_t i = 0; i < img.pixels.size(); i += 4)
        if (img.pixels[i] + img.pixels[i + 1] + img.pixels[i + 2] > 60) ++lit;
    return double(lit) / double(img.width * img.height);
}

TEST_F(GlobeRender, DefaultViewMatchesGolden) {
    const auto img = render(globeScene(R"({"lon": 5, "lat": 28, "range": 19000000})"));
    EXPECT_TRUE(matchesGolden(img, "globe_default"));
}

TEST_F(GlobeRender, NorthPoleClosesWithoutHole) {
    const auto img = render(globeScene(R"({"lon": 0, "lat": 90, "range": 9000000})", "", "2026-06-21T12:00:00Z"));
    EXPECT_TRUE(matchesGolden(img, "globe_north_pole"));
    // The pole is the centre of the image: it must be surface, not background.
    const size_t c = (size_t(img.height / 2) * img.width + img.width / 2) * 4;
    EXPECT_GT(img.pixels[c] + img.pixels[c + 1] + img.pixels[c + 2], 60) << "hole at the pole";
}

TEST_F(GlobeRender, AntimeridianHasNoSeam) {
    // Looking straight at lon 180 from low orbit: a seam would show background pixels in a
    // vertical line through the centre. The disc must be solid along that column.
    // At 00:00 UTC on the equinox the sun is over the antimeridian: the view is in daylight.
    const auto img = render(
        globeScene(R"({"lon": 180, "lat": 0, "range": 3000000})", R"(, "graticuleDeg": 0)", "2026-03-20T00:00:00Z"));
    EXPECT_TRUE(matchesGolden(img, "globe_antimeridian"));
    const uint32_t x = img.width / 2;
    for (uint32_t y = img.height / 4; y < 3 * img.height / 4; ++y) {
        const size_t i = (size_t(y) * img.width + x) * 4;
        ASSERT_GT(img.pixels[i] + img.pixels[i + 1] + img.pixels[i + 2], 30) << "background pixel at y=" << y;
    }
}

TEST_F(GlobeRender, CameraFortyThousandKilometresOut) {
    const auto img = render(globeScene(R"({"lon": -60, "lat": -10, "range": 40000000})"));
    EXPECT_TRUE(matchesGolden(img, "globe_far"));
    // Angular radius of the Earth from 40 000 km: asin(6371/46371) ~ 7.9 deg, against a 45 deg
    // vertical field of view: the disc covers roughly pi*(0.3*240/2)^2 / (320*240) of the image.
    const double c = coverage(img);
    EXPECT_GT(c, 0.02);
    EXPECT_LT(c, 0.15);
}

TEST_F(GlobeRender, OneMetreAboveGroundShowsHorizonAndNoJitter) {
    // Eye 1 m above the ellipsoid at lat 45, looking level towards the east.
    const std::string a = globeScene(R"({"lon": 7, "lat": 45, "height": 0, "heading": 90, "pitch": -5, "range": 11.474})");
    // The same view moved 1 mm east (1 mm / (a cos 45) rad of longitude).
    const double dLon = 0.001 / (6378137.0 * std::cos(glm::radians(45.0))) * 180.0 / glm::pi<double>();
    const std::string lon = std::to_string(7.0 + dLon);
    char vp[256];
    std::snprintf(vp, sizeof vp, R"({"lon": %.15f, "lat": 45, "height": 0, "heading": 90, "pitch": -5, "range": 11.474})",
                  7.0 + dLon);
    const auto imgA = render(a);
    const auto imgB = render(globeScene(vp));
    EXPECT_TRUE(matchesGolden(imgA, "globe_one_metre"));
    // Ground fills the bottom, sky the top.
    const size_t bottom = (size_t(imgA.height - 2) * imgA.width + imgA.width / 2) * 4;
    const size_t top = (size_t(1) * imgA.width + imgA.width / 2) * 4;
    EXPECT_NE(imgA.pixels[bottom + 2], imgA.pixels[top + 2]) << "no horizon";
    // No jitter: 1 mm of camera motion changes no pixel beyond the golden tolerance.
    EXPECT_TRUE(imagesAgree(imgA, imgB, "globe_one_metre_jitter", 5));
}

TEST_F(GlobeRender, NightSideIsDarkerThanDaySide) {
    // At 12:00 UTC on the equinox the sun is over lon ~0: lon 0 is day, lon 180 is night.
    const auto day = render(globeScene(R"({"lon": 0, "lat": 0, "range": 20000000})", R"(, "sky": false)"));
    const auto night = render(globeScene(R"({"lon": 180, "lat": 0, "range": 20000000})", R"(, "sky": false)"));
    const size_t c = (size_t(day.height / 2) * day.width + day.width / 2) * 4;
    EXPECT_GT(day.pixels[c + 2], night.pixels[c + 2] + 60);
}

TEST_F(GlobeRender, SameSceneRendersIdentically) {
    const std::string json = globeScene(R"({"lon": 30, "lat": 10, "range": 15000000})");
    const auto a = render(json), b = render(json);
    EXPECT_TRUE(imagesAgree(a, b, "globe_repeat", 0));
}

}  // namespace
}  // namespace orbis::test
