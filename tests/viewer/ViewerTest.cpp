// orbis view under Xvfb: the viewer opens a scene, scripted input moves the camera and works
// the panels, and each screenshot (the swapchain's picture, panels included) is compared with
// its golden image. Every run has the Khronos validation layer on: the viewer exits with 1 if
// it reported anything, so exit code 0 also means a clean shutdown.
#include "tests/support/GoldenImage.h"
#include "tests/support/ProcessTempDir.h"
#include "tests/support/Shell.h"
#include "tests/support/WpsServer.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <future>
#include <regex>
#include <string>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;

using ViewerRun = ShellRun;

ViewerRun shell(const std::string& cmd) { return runShell(cmd); }

bool haveXvfb() { return shell("command -v Xvfb").exitCode == 0; }

/// `cmd` with DISPLAY set to a private Xvfb: -displayfd lets the server pick a free display
/// and say which when it is ready, so tests in parallel never race for one (xvfb-run -a can,
/// and its clean-up fails now and then under load).
std::string underXvfb(const std::string& cmd) {
    return "f=$(mktemp) && { Xvfb -displayfd 3 -screen 0 1280x720x24 -nolisten tcp 3>\"$f\" 2>/dev/null & xp=$!; }; "
           "for i in $(seq 400); do [ -s \"$f\" ] && break; sleep 0.05; done; d=$(head -n 1 \"$f\"); rm -f \"$f\"; "
           "if [ -z \"$d\" ]; then echo Xvfb did not start; kill $xp; exit 70; fi; "
           "DISPLAY=:$d " + cmd + "; rc=$?; kill $xp; wait $xp 2>/dev/null; exit $rc";
}

/// A fresh folder for one test's script and screenshots.
fs::path workDir(const std::string& name) {
    const fs::path dir = processTempDir("orbis-viewer-test") / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

/// Runs the viewer on `scene` with `script` (JSON text) at 960x540 (or `size`) under its own Xvfb.
ViewerRun view(const fs::path& dir, const std::string& script, const std::string& scene = ORBIS_DEFAULT_SCENE,
         const std::string& extra = "", const std::string& moreEnv = "", const std::string& size = "960x540") {
    std::ofstream(dir / "script.json") << script;
    const std::string env = "XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp} "
                            "VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json " + moreEnv;
    return shell(underXvfb(env + ORBIS_BINARY + " view \"" + scene + "\" --device cpu --validation --size " + size + " --script \"" +
                           (dir / "script.json").string() + "\" " + extra));
}

/// A file's whole text (empty when it cannot be read).
std::string readText(const fs::path& file) {
    std::ifstream in(file);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

ImageRgba8 shot(const fs::path& file) {
    auto image = readPng(file);
    EXPECT_TRUE(image) << file << ": " << (image ? "" : image.message());
    return image ? *image : ImageRgba8{};
}

#define REQUIRE_XVFB() \
    if (!haveXvfb()) GTEST_SKIP() << "Xvfb is not installed (tools/install-deps.sh installs it)"

TEST(Viewer, NavigatesWithScriptedInput) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("navigate");
    const ViewerRun r = view(dir, R"([
        {"do": "settle"}, {"do": "screenshot", "file": "home.png"},
        {"do": "drag", "button": "left", "from": [560, 300], "to": [480, 260], "frames": 6},
        {"do": "settle"}, {"do": "screenshot", "file": "rotate.png"},
        {"do": "scroll", "at": [600, 300], "lines": 4},
        {"do": "settle"}, {"do": "screenshot", "file": "zoom.png"},
        {"do": "drag", "button": "middle", "from": [600, 300], "to": [660, 240], "frames": 6},
        {"do": "settle"}, {"do": "screenshot", "file": "tilt.png"},
        {"do": "doubleClick", "at": [640, 330]},
        {"do": "settle"}, {"do": "screenshot", "file": "fly.png"},
        {"do": "key", "key": "Home"},
        {"do": "settle"}, {"do": "screenshot", "file": "home-again.png"},
        {"do": "quit"}])");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const char* name : {"home", "rotate", "zoom", "tilt", "fly"})
        EXPECT_TRUE(matchesGolden(shot(dir / (std::string(name) + ".png")), std::string("viewer_") + name)) << name;
    // Home flies back to the scene's viewpoint: the picture of the start, but for the status line.
    const ImageRgba8 a = shot(dir / "home.png"), b = shot(dir / "home-again.png");
    ASSERT_EQ(a.width, 960u);
    EXPECT_LT(countDifferentPixels(a, b, 8), size_t(960 * 24)) << "Home did not return to the start";
    // Each step moved the camera.
    EXPECT_GT(countDifferentPixels(a, shot(dir / "rotate.png"), 8), size_t(20000));
    EXPECT_GT(countDifferentPixels(shot(dir / "rotate.png"), shot(dir / "zoom.png"), 8), size_t(20000));
}

TEST(Viewer, PanelTogglesALayer) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("toggle");
    const ViewerRun r = view(dir, R"([
        {"do": "settle"}, {"do": "screenshot", "file": "on.png"},
        {"do": "click", "item": "Visible##Synthetic planet"},
        {"do": "settle"}, {"do": "screenshot", "file": "off.png"},
        {"do": "click", "item": "Visible##Synthetic planet"},
        {"do": "settle"}, {"do": "screenshot", "file": "on-again.png"},
        {"do": "quit"}])");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const ImageRgba8 on = shot(dir / "on.png"), off = shot(dir / "off.png"), again = shot(dir / "on-again.png");
    EXPECT_TRUE(matchesGolden(off, "viewer_layer_hidden"));
    EXPECT_GT(countDifferentPixels(on, off, 8), size_t(50000)) << "hiding the terrain should remove the globe";
    EXPECT_LT(countDifferentPixels(on, again, 8), size_t(960 * 24));
}

TEST(Viewer, SavedSceneRendersTheView) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("save");
    // The panels hidden (F1): the screenshot is the scene alone, as orbis render draws it.
    const std::string script = R"([
        {"do": "settle"},
        {"do": "drag", "button": "left", "from": [560, 300], "to": [470, 250], "frames": 4},
        {"do": "scroll", "at": [480, 270], "lines": 3},
        {"do": "drag", "button": "middle", "from": [480, 300], "to": [520, 250], "frames": 4},
        {"do": "settle"}, {"do": "key", "key": "F1"}, {"do": "screenshot", "file": "view.png"},
        {"do": "key", "key": "Ctrl+S"}, {"do": "quit"}])";
    const ViewerRun r = view(dir, script,
                             ORBIS_DEFAULT_SCENE, "--save-to \"" + (dir / "saved" / "view.json").string() + "\"");
    ASSERT_EQ(r.exitCode, 1) << "the folder does not exist yet: the save must fail clearly\n" << r.output;
    EXPECT_NE(r.output.find("view.json"), std::string::npos) << r.output;
    fs::create_directories(dir / "saved");
    const ViewerRun ok = view(dir, script,
                              ORBIS_DEFAULT_SCENE, "--save-to \"" + (dir / "saved" / "view.json").string() + "\"");
    ASSERT_EQ(ok.exitCode, 0) << ok.output;
    ASSERT_TRUE(fs::exists(dir / "saved" / "view.json")) << ok.output;
    const ViewerRun render = shell("XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp} VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json " +
                                   std::string(ORBIS_BINARY) + " render '" + (dir / "saved" / "view.json").string() +
                                   "' -o '" + (dir / "rendered.png").string() + "' --size 960x540 --device cpu --validation");
    ASSERT_EQ(render.exitCode, 0) << render.output;
    const ImageRgba8 viewed = shot(dir / "view.png"), rendered = shot(dir / "rendered.png");
    // The saved viewpoint is the pose in lon/lat/height/heading/pitch/range, rounded through
    // text: sub-pixel differences along edges at most.
    EXPECT_TRUE(imagesAgree(viewed, rendered, "viewer_saved_scene", 24, 960 * 540 / 200));
}

TEST(Viewer, PlacesDeletesAndSavesPins) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("pins");
    // Place pin, click the globe; the pin shows, is saved (the panels hidden for the render
    // comparison), then deleted from the list.
    const ViewerRun r = view(dir, R"([
        {"do": "settle"}, {"do": "screenshot", "file": "none.png"},
        {"do": "click", "item": "Place pin"}, {"do": "click", "at": [470, 300]},
        {"do": "settle"}, {"do": "screenshot", "file": "pin.png"},
        {"do": "key", "key": "F1"}, {"do": "screenshot", "file": "clean.png"},
        {"do": "key", "key": "Ctrl+S"}, {"do": "key", "key": "F1"},
        {"do": "click", "item": "Delete##pin0"},
        {"do": "settle"}, {"do": "screenshot", "file": "deleted.png"},
        {"do": "click", "item": "Place pin"}, {"do": "key", "key": "Escape"},
        {"do": "settle"}, {"do": "quit"}])",
                             ORBIS_DEFAULT_SCENE, "--save-to \"" + (dir / "pins.json").string() + "\"");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("wrote"), std::string::npos);
    const ImageRgba8 none = shot(dir / "none.png"), pin = shot(dir / "pin.png"), deleted = shot(dir / "deleted.png");
    EXPECT_TRUE(matchesGolden(pin, "viewer_pin"));
    EXPECT_GT(countDifferentPixels(none, pin, 8), size_t(600)) << "no pin drawn";

    // The pin went into the saved scene at the point clicked: the centre of the default view
    // looks at lon 5, lat 28; 10 px left and 30 px below it is a little west and south.
    const std::string text = readText(dir / "pins.json");
    const std::regex pinRe(R"re("lat": ([-0-9.e]+),\s*"lon": ([-0-9.e]+),\s*"name": "Pin 1")re");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(text, m, pinRe)) << text;
    const double lat = std::stod(m[1]), lon = std::stod(m[2]);
    EXPECT_GT(lat, 15.0);
    EXPECT_LT(lat, 28.0);
    EXPECT_GT(lon, -3.0);
    EXPECT_LT(lon, 5.0);
    const ViewerRun render = shell("XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp} VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json " +
                                   std::string(ORBIS_BINARY) + " render '" + (dir / "pins.json").string() + "' -o '" +
                                   (dir / "rendered.png").string() + "' --size 960x540 --device cpu --validation");
    ASSERT_EQ(render.exitCode, 0) << render.output;
    EXPECT_TRUE(imagesAgree(shot(dir / "clean.png"), shot(dir / "rendered.png"), "viewer_pin_saved", 24, 960 * 540 / 200));
    // Deleted: the picture of the start again, but for the status line.
    EXPECT_LT(countDifferentPixels(none, deleted, 8), size_t(960 * 24));
}

TEST(Viewer, ShiftDragMovesTheViewshedsObserverAndTheSceneKeepsIt) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("viewshed");
    // assets/scenes/viewshed.json: Shift + drag from near the mast to the south-west; the
    // viewshed is computed again there (the drape changes), the camera stays, and the saved
    // scene holds the new observer.
    const ViewerRun r = view(dir, R"([
        {"do": "settle"}, {"do": "key", "key": "F1"}, {"do": "screenshot", "file": "before.png"},
        {"do": "drag", "from": [480, 300], "to": [380, 340], "frames": 4, "shift": true},
        {"do": "settle"}, {"do": "screenshot", "file": "after.png"},
        {"do": "key", "key": "Ctrl+S"}, {"do": "quit"}])",
                             std::string(ORBIS_SOURCE_DIR) + "/assets/scenes/viewshed.json",
                             "--save-to \"" + (dir / "moved.json").string() + "\"");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const ImageRgba8 before = shot(dir / "before.png"), after = shot(dir / "after.png");
    EXPECT_GT(countDifferentPixels(before, after, 16), size_t(960 * 540 / 50)) << "the drape did not change";
    // The terrain's corners, outside the drape: the camera did not move.
    for (const auto& [x, y] : {std::pair{20u, 20u}, std::pair{940u, 20u}, std::pair{20u, 520u}, std::pair{940u, 520u}})
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(int(before.pixels[(size_t(y) * 960 + x) * 4 + c]), int(after.pixels[(size_t(y) * 960 + x) * 4 + c]), 6) << x << "," << y;
    const std::string text = readText(dir / "moved.json");
    const std::regex observerRe(R"re("observer": \[\s*([-0-9.e]+),\s*([-0-9.e]+)\s*\])re");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(text, m, observerRe)) << text;
    const double lon = std::stod(m[1]), lat = std::stod(m[2]);
    EXPECT_LT(lon, 9.03 - 0.002) << "moved west";
    EXPECT_LT(lat, 46.02 - 0.001) << "moved south";
    EXPECT_GT(lon, 9.0);
    EXPECT_GT(lat, 46.0);
}

/// Pixels of `a` and `b` that differ by more than `tolerance` in a channel, within a rectangle.
size_t differentPixelsIn(const ImageRgba8& a, const ImageRgba8& b, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, int tolerance) {
    size_t n = 0;
    for (uint32_t y = y0; y < y1 && y < a.height; ++y)
        for (uint32_t x = x0; x < x1 && x < a.width; ++x)
            for (int c = 0; c < 3; ++c)
                if (std::abs(int(a.pixels[(size_t(y) * a.width + x) * 4 + c]) - int(b.pixels[(size_t(y) * b.width + x) * 4 + c])) > tolerance) {
                    ++n;
                    break;
                }
    return n;
}

TEST(Viewer, AProcessRunsOnADrawnBoxAndItsResultIsALayerSavedWithTheScene) {
    REQUIRE_XVFB();
    const std::string dem = std::string(ORBIS_SOURCE_DIR) + "/assets/generated/fmv/flight-dem.tif";
    if (!fs::exists(dem)) GTEST_SKIP() << dem << " is generated by the build";
    WpsServer wps(dem);
    if (!wps.available()) GTEST_SKIP() << wps.error();
    ASSERT_TRUE(wps.running()) << wps.error();
    const fs::path dir = workDir("processes");
    // assets/scenes/processing.json at 1280x720: connect to the demo server, choose the terrain
    // process (slope by default), draw a box with the Measure panel, Run; the slope comes back
    // as an overlay on the box, and Ctrl+S saves it with its provenance.
    const ViewerRun r = view(dir, R"([
        {"do": "settle"},
        {"do": "click", "item": "Connect##wps"}, {"do": "settle"},
        {"do": "click", "item": "terrain##process"}, {"do": "settle"},
        {"do": "click", "item": "Box##tool"}, {"do": "settle"},
        {"do": "click", "at": [600, 300]}, {"do": "click", "at": [720, 420]}, {"do": "settle"},
        {"do": "screenshot", "file": "drawn.png"},
        {"do": "click", "item": "Run##wps"}, {"do": "settle"},
        {"do": "screenshot", "file": "result.png"},
        {"do": "key", "key": "Ctrl+S"}, {"do": "quit"}])",
                             std::string(ORBIS_SOURCE_DIR) + "/assets/scenes/processing.json",
                             "--wps " + wps.url() + " --results \"" + (dir / "results").string() + "\" --save-to \"" + (dir / "saved.json").string() + "\"",
                             "", "1280x720");
    ASSERT_EQ(r.exitCode, 0) << r.output << "\n" << wps.log();
    EXPECT_NE(r.output.find("added layer \"Slope, aspect or hillshade of the DEM in an area\""), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("result on screen"), std::string::npos) << r.output;
    // Inside the box the slope is painted over the bare ground; outside it nothing changed.
    const ImageRgba8 drawn = shot(dir / "drawn.png"), result = shot(dir / "result.png");
    EXPECT_GT(differentPixelsIn(drawn, result, 610, 310, 710, 410, 12), size_t(100 * 100 / 2)) << "the slope is not on the box";
    EXPECT_LT(differentPixelsIn(drawn, result, 360, 180, 560, 260, 12), size_t(200)) << "the ground outside the box changed";

    const auto saved = nlohmann::json::parse(readText(dir / "saved.json"), nullptr, false);
    ASSERT_TRUE(saved.is_object()) << readText(dir / "saved.json");
    ASSERT_EQ(saved["layers"].size(), 2u) << saved.dump(1);
    const auto& layer = saved["layers"][1];
    EXPECT_EQ(layer["type"], "overlay");
    EXPECT_EQ(layer["provenance"]["process"], "terrain");
    EXPECT_EQ(layer["provenance"]["wps"], wps.url());
    EXPECT_EQ(layer["provenance"]["inputs"]["product"], "slope");
    ASSERT_EQ(layer["provenance"]["inputs"]["area"].size(), 4u);
    const double west = layer["provenance"]["inputs"]["area"][0], east = layer["provenance"]["inputs"]["area"][2];
    EXPECT_GT(east - west, 0.005) << "the drawn box, about 1 km wide";
    EXPECT_EQ(layer["provenance"]["reference"].get<std::string>().rfind(wps.url().substr(0, wps.url().rfind('/')), 0), 0u) << layer.dump();
    const fs::path raster = dir / layer["path"].get<std::string>();
    EXPECT_TRUE(fs::exists(raster)) << raster;
    // The saved scene renders the result headless, as the viewer showed it.
    const ViewerRun render = shell("VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json " + std::string(ORBIS_BINARY) + " render \"" +
                                   (dir / "saved.json").string() + "\" --device cpu --validation --size 480x270 -o \"" +
                                   (dir / "saved.png").string() + "\"");
    ASSERT_EQ(render.exitCode, 0) << render.output;
    EXPECT_TRUE(matchesGolden(shot(dir / "saved.png"), "viewer_processing_result"));
}

TEST(Viewer, MeasureToolsDrawAPathWithItsLengthAndALineOfSight) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("measure");
    // The viewshed's hills: a path across the ridge, then a line of sight through it from low
    // ground on one side to low ground on the other: drawn in the window, green then red.
    const ViewerRun r = view(dir, R"([
        {"do": "settle"},
        {"do": "click", "item": "Path##tool"}, {"do": "settle"},
        {"do": "screenshot", "file": "empty.png"},
        {"do": "click", "at": [380, 330]}, {"do": "click", "at": [640, 330]}, {"do": "click", "at": [800, 380]}, {"do": "settle"},
        {"do": "screenshot", "file": "path.png"},
        {"do": "click", "item": "Sight##tool"}, {"do": "settle"},
        {"do": "click", "at": [420, 400]}, {"do": "click", "at": [800, 400]}, {"do": "settle"},
        {"do": "screenshot", "file": "sight.png"}, {"do": "quit"}])",
                             std::string(ORBIS_SOURCE_DIR) + "/assets/scenes/processing.json", "", "", "1280x720");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const ImageRgba8 empty = shot(dir / "empty.png"), path = shot(dir / "path.png"), sight = shot(dir / "sight.png");
    const auto count = [](const ImageRgba8& img, auto&& test) {
        size_t n = 0;
        for (size_t i = 0; i < size_t(img.width) * img.height; ++i) n += test(&img.pixels[i * 4]);
        return n;
    };
    const auto yellow = [](const uint8_t* p) { return p[0] > 200 && p[1] > 170 && p[2] < 110; };
    const auto green = [](const uint8_t* p) { return p[1] > 180 && p[0] < 120 && p[2] < 140; };
    const auto red = [](const uint8_t* p) { return p[0] > 200 && p[1] < 100 && p[2] < 100; };
    EXPECT_LT(count(empty, yellow), size_t(50));
    EXPECT_GT(count(path, yellow), size_t(600)) << "the path's line and points";
    EXPECT_GT(count(sight, green), size_t(100)) << "the sight line up to the ridge";
    EXPECT_GT(count(sight, red), size_t(100)) << "blocked past the ridge";
}

TEST(Viewer, TransferFunctionEditorChangesTheVolume) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("transfer");
    std::ofstream(dir / "volume.json") << R"({
      "viewpoint": {"lon": 0, "lat": 50, "height": 400000, "heading": 0, "pitch": -40, "range": 4200000},
      "time": {"start": "2026-06-21T12:00:00Z", "end": "2026-06-21T12:00:00Z"},
      "layers": [{"type": "globe", "name": "Earth"},
        {"type": "volume", "name": "Waves", "steps": 64, "colorMap": "magma", "range": [-1, 1],
         "synthetic": {"field": "waves", "size": [32, 32, 32], "lon": [-10, 10], "lat": [40, 60], "height": [0, 800000]},
         "opacity": [[-1, 0.0], [0.2, 0.0], [0.6, 0.15], [1, 0.6]]}]})";
    // The point (0.6, 0.15) sits at 80 % across and 85 % down the editor (x over [-1, 1], alpha
    // 0..1 upward): drag it up and left.
    const ViewerRun r = view(dir, R"([
        {"do": "settle"}, {"do": "screenshot", "file": "before.png"},
        {"do": "drag", "item": "opacity##Waves", "from": [0.8, 0.85], "to": [0.7, 0.25], "frames": 4},
        {"do": "settle"}, {"do": "screenshot", "file": "after.png"},
        {"do": "key", "key": "Ctrl+S"}, {"do": "quit"}])",
                             (dir / "volume.json").string(), "--save-to \"" + (dir / "saved.json").string() + "\"");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const ImageRgba8 before = shot(dir / "before.png"), after = shot(dir / "after.png");
    EXPECT_TRUE(matchesGolden(after, "viewer_transfer_function"));
    EXPECT_GT(countDifferentPixels(before, after, 8), size_t(20000)) << "more opacity should show in the volume";
    const std::string text = readText(dir / "saved.json");
    // The moved point: x from 0.6 to about 0.4, alpha from 0.15 to about 0.75; the others stay.
    const std::regex moved(R"re("opacity": \[\s*\[\s*-1\.0,\s*0\.0\s*\],\s*\[\s*0\.2,\s*0\.0\s*\],\s*\[\s*0\.(3[6-9]|4[0-4])[0-9]*,\s*0\.(7[0-9])[0-9]*\s*\],\s*\[\s*1\.0,\s*0\.6\s*\]\s*\])re");
    EXPECT_TRUE(std::regex_search(text, moved)) << text;
}

TEST(Viewer, SleepsWhenIdle) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("idle");
    const ViewerRun r = view(dir, R"([{"do": "settle"}, {"do": "idle", "seconds": 5}, {"do": "quit"}])");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(idle: ([0-9.]+) s of CPU over ([0-9.]+) s)"))) << r.output;
    const double cpu = std::stod(m[1]), seconds = std::stod(m[2]);
    std::printf("idle CPU: %.3f s over %.1f s\n", cpu, seconds);
    // Drawing even 2 frames a second on lavapipe would cost far more than this.
    EXPECT_LT(cpu / seconds, 0.05) << r.output;
}

TEST(Viewer, ALayerThatFailsToLoadShowsItsErrorAndTheRestLoads) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("failed-layer");
    std::ofstream(dir / "scene.json") << R"({
      "viewpoint": {"lon": 5, "lat": 28, "range": 19000000},
      "time": {"start": "2026-03-20T12:00:00Z", "end": "2026-03-20T12:00:00Z"},
      "layers": [{"type": "globe", "name": "Earth"},
                 {"type": "points", "name": "Survey", "path": "no-such-cloud.las"}]})";
    const ViewerRun r = view(dir, R"([{"do": "settle"}, {"do": "screenshot", "file": "shot.png"},
                                      {"do": "click", "item": "Visible##Survey"}, {"do": "settle"},
                                      {"do": "key", "key": "Ctrl+S"}, {"do": "quit"}])",
                             (dir / "scene.json").string(), "--save-to \"" + (dir / "saved.json").string() + "\"");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("no-such-cloud.las"), std::string::npos) << r.output;
    // The globe loaded (the centre of the view is not background); the panel shows the error
    // (its text names the test's folder, so no golden image here).
    const ImageRgba8 image = shot(dir / "shot.png");
    ASSERT_EQ(image.width, 960u);
    const size_t c = (size_t(image.height / 2) * image.width + image.width / 2) * 4;
    EXPECT_GT(image.pixels[c] + image.pixels[c + 1] + image.pixels[c + 2], 90);
    // The saved scene keeps the layer as the file had it: it loads once the file is there.
    const std::string text = readText(dir / "saved.json");
    EXPECT_NE(text.find("no-such-cloud.las"), std::string::npos) << text;
    EXPECT_EQ(text.find("\"visible\": false"), std::string::npos) << text;
}

TEST(Viewer, TerminationClosesCleanlyAndKeepsThePanelLayout) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("layout");
    // An interactive session (no script) keeps its panel layout in $XDG_CONFIG_HOME/orbis;
    // SIGTERM (or Ctrl+C) closes it as the window's close button does: exit 0, no validation
    // message, the layout written.
    const std::string run = "XDG_CONFIG_HOME='" + dir.string() + "' XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp} " +
                            "VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json " + ORBIS_BINARY + " view \"" +
                            ORBIS_DEFAULT_SCENE + "\" --device cpu --validation --size 640x400";
    const ViewerRun r = shell(underXvfb("bash -c \"" + run + " & p=\\$!; sleep 4; kill -TERM \\$p; wait \\$p\""));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    const std::string text = readText(dir / "orbis" / "viewer-layout.ini");
    EXPECT_NE(text.find("[Window][Resources]"), std::string::npos) << text;
}

// The GPU device lost in the middle of a session (injected: a driver's VK_ERROR_DEVICE_LOST
// cannot be provoked on demand, so the 60th submit reports it as the driver would): a clear
// message, exit 3, no hang and no crash on the way out, and the view saved where Ctrl+S saves
// it, ready to open again.
TEST(Viewer, DeviceLostSavesTheViewAndExitsCleanly) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("lost");
    const fs::path saved = dir / "recovered.json";
    const std::string script = R"([
        {"do": "settle"},
        {"do": "drag", "button": "left", "from": [560, 300], "to": [470, 250], "frames": 200},
        {"do": "settle"}, {"do": "quit"}])";
    const ViewerRun r = view(dir, script, ORBIS_DEFAULT_SCENE, "--save-to \"" + saved.string() + "\"",
                             "ORBIS_FAULT_DEVICE_LOST_AFTER=60 ");
    EXPECT_EQ(r.exitCode, 3) << r.output;
    EXPECT_NE(r.output.find("the GPU device was lost"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("saved to " + saved.string()), std::string::npos) << r.output;
    ASSERT_TRUE(fs::exists(saved)) << r.output;
    const ViewerRun render = shell("XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp} VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json " +
                                   std::string(ORBIS_BINARY) + " render '" + saved.string() + "' -o '" +
                                   (dir / "rendered.png").string() + "' --size 320x180 --device cpu --validation");
    EXPECT_EQ(render.exitCode, 0) << render.output;
}

TEST(Viewer, TheFeedsPanelLooksThroughALiveSensor) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("feeds");
    const ShellRun port = shell("python3 -c 'import socket; s=socket.socket(socket.AF_INET, socket.SOCK_DGRAM); "
                                "s.bind((\"127.0.0.1\", 0)); print(s.getsockname()[1])'");
    ASSERT_EQ(port.exitCode, 0) << port.output;
    const std::string url = "udp://127.0.0.1:" + std::to_string(std::stoi(port.output));
    std::ofstream(dir / "live.json") << R"({"viewpoint": {"lon": 9.03, "lat": 46.02, "height": 650, "heading": 0, "pitch": -60, "range": 9000},
        "background": [0.1, 0.1, 0.15], "layers": [
        {"type": "terrain", "name": "Ground", "sky": false, "elevation": [")" ORBIS_SOURCE_DIR R"(/assets/generated/fmv/flight-dem.tif"]},
        {"type": "fmv", "name": "UAV", "url": ")" + url + R"(", "wholeFrames": true, "noSignal": 5}]})";
    // The flight sent while the viewer runs (at most 60 s; stopped when the viewer is done).
    const ShellRun started = shell("timeout 60 " + std::string(ORBIS_MAKE_FMV) + " --stream " + url +
                                   " --frames 600 --size 320x240 --wall-clock > /dev/null 2>&1 & echo $!");
    ASSERT_EQ(started.exitCode, 0) << started.output;
    const std::string senderPid = std::to_string(std::stol(started.output));
    const ViewerRun r = view(dir, R"([
        {"do": "idle", "seconds": 2}, {"do": "screenshot", "file": "overview.png"},
        {"do": "click", "item": "Sensor view##UAV"}, {"do": "idle", "seconds": 3}, {"do": "screenshot", "file": "sensor.png"},
        {"do": "key", "key": "Ctrl+S"},
        {"do": "click", "item": "Record##UAV"}, {"do": "idle", "seconds": 2.5}, {"do": "click", "item": "Record##UAV"},
        {"do": "idle", "seconds": 0.5}, {"do": "quit"}])",
                             (dir / "live.json").string(), "--save-to \"" + (dir / "saved.json").string() + "\"");
    shell("kill " + senderPid + " 2>/dev/null");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // Looking through the sensor, its own video fills the middle of the view: the checkerboard's
    // greys (60 and 200, equal channels), where the overview shows the terrain's blue.
    const ImageRgba8 overview = shot(dir / "overview.png"), sensor = shot(dir / "sensor.png");
    ASSERT_EQ(sensor.pixels.size(), size_t(960 * 540 * 4));
    size_t grey = 0, total = 0;
    for (uint32_t y = 170; y < 370; ++y)
        for (uint32_t x = 330; x < 630; ++x, ++total) {
            const uint8_t* p = &sensor.pixels[(size_t(y) * 960 + x) * 4];
            grey += std::abs(int(p[0]) - int(p[2])) < 20 && std::abs(int(p[1]) - int(p[2])) < 20 ? 1 : 0;
        }
    EXPECT_GT(grey, total / 2) << "the middle of the sensor's view is not its video";
    EXPECT_GT(countDifferentPixels(overview, sensor, 24), size_t(960 * 540 / 6));
    for (const char* name : {"overview.png", "sensor.png"})   // to look at
        fs::copy_file(dir / name, fs::path(testOutputDir()) / (std::string("viewer_feeds_") + name), fs::copy_options::overwrite_existing);
    const std::string saved = readText(dir / "saved.json");
    EXPECT_NE(saved.find("\"pilot\""), std::string::npos) << saved;
    // Record, then Stop: a file next to the scene, named after the layer, that plays as a video.
    std::vector<fs::path> recordings;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".ts" && e.path().filename().string().rfind("UAV-", 0) == 0) recordings.push_back(e.path());
    ASSERT_EQ(recordings.size(), 1u) << r.output;
    const ShellRun info = shell(std::string(ORBIS_BINARY) + " info '" + recordings[0].string() + "'");
    EXPECT_EQ(info.exitCode, 0) << info.output;
    EXPECT_NE(info.output.find("\"klvPackets\":"), std::string::npos) << info.output.substr(0, 400);
}

TEST(Viewer, BadInputsGiveClearErrors) {
    REQUIRE_XVFB();
    const fs::path dir = workDir("bad");
    ViewerRun r = view(dir, R"([{"do": "jump"}])");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("step 1: unknown \"do\": \"jump\""), std::string::npos) << r.output;
    r = view(dir, "[{\"do\": \"screenshot\"}]");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("screenshot needs \"file\""), std::string::npos) << r.output;
    r = view(dir, "not json");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("not valid JSON"), std::string::npos) << r.output;
    r = view(dir, "[]", (dir / "missing.json").string());
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("missing.json"), std::string::npos) << r.output;
    r = view(dir, R"([{"do": "settle"}, {"do": "click", "item": "No such button"}])");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("no item \"No such button\""), std::string::npos) << r.output;
    r = shell(std::string(ORBIS_BINARY) + " view " + ORBIS_DEFAULT_SCENE + " --wps ftp://example.org/wps");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("--wps: \"ftp://example.org/wps\" is not an http(s) address"), std::string::npos) << r.output;
    // A processing server that is not there: the panel says so, nothing hangs or crashes.
    r = view(dir, R"([{"do": "settle"}, {"do": "click", "item": "Connect##wps"}, {"do": "settle"}, {"do": "quit"}])", ORBIS_DEFAULT_SCENE,
             "--wps http://127.0.0.1:1/wps");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    // No display at all.
    r = shell(std::string("env -u DISPLAY -u WAYLAND_DISPLAY ") + ORBIS_BINARY + " view " + ORBIS_DEFAULT_SCENE);
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("no display"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace orbis::test
