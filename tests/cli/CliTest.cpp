// The orbis command line: bad arguments exit 2, bad input exits 1 with a one-line message that
// names the file and the problem, and nothing crashes. GPU commands run on lavapipe.
#include "tests/support/GpuTest.h"
#include "tests/support/Shell.h"
#include "tests/unit/GltfTestFiles.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;

using CliRun = ShellRun;

CliRun run(const std::string& args) { return runShell(std::string(ORBIS_BINARY) + " " + args); }

std::string jsonString(const std::string& s) { return nlohmann::json(s).dump(); }

fs::path tempFile(const std::string& name, const std::string& content) {
    const fs::path dir = fs::temp_directory_path() / "orbis-cli-test";
    fs::create_directories(dir);
    const fs::path p = dir / name;
    std::ofstream(p, std::ios::binary) << content;
    return p;
}

TEST(Cli, NoArgumentsIsUsage) {
    const CliRun r = run("");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("usage: orbis"), std::string::npos);
}

TEST(Cli, HelpExitsZeroForEveryCommand) {
    for (const char* c : {"--help", "render --help", "bench --help", "info --help", "measure --help", "viewshed --help", "wps --help"}) {
        const CliRun r = run(c);
        EXPECT_EQ(r.exitCode, 0) << c << ": " << r.output;
        EXPECT_NE(r.output.find("usage:"), std::string::npos) << c;
    }
}

TEST(Cli, UsageErrorsExitTwo) {
    const std::string scene = ORBIS_DEFAULT_SCENE;
    const char* cases[] = {"frobnicate", "render", "render " ORBIS_DEFAULT_SCENE, "render a b -o x.png",
                           "render " ORBIS_DEFAULT_SCENE " -o x.png --size 0x10",
                           "render " ORBIS_DEFAULT_SCENE " -o x.png --size big",
                           "render " ORBIS_DEFAULT_SCENE " -o x.png --bogus",
                           "render " ORBIS_DEFAULT_SCENE " -o",
                           "render " ORBIS_DEFAULT_SCENE " -o x.png --time 1999-01-01T00:00:00Z",
                           "render " ORBIS_DEFAULT_SCENE " -o x.png --time noon",
                           "bench " ORBIS_DEFAULT_SCENE " --frames 0",
                           "bench " ORBIS_DEFAULT_SCENE " --frames ten",
                           "info a b", "--nonsense info", "measure", "measure --path \"0,0\"", "measure --path \"0,0 1,x\"",
                           "measure --path \"0,0 1,95\"", "measure --path \"0,0 1,1\" --sight \"0,0,1 1,1,1\"",
                           "measure --sight \"0,0,1 1,1,1\"", "measure --path \"0,0 1,1\" --polygon",
                           "measure --path \"0,0 1,1\" --csv x.csv", "viewshed", "viewshed --synthetic 1 --radius 100",
                           "viewshed --synthetic 1 --dem x.tif --observer 0,0 --radius 100",
                           "viewshed --synthetic 1 --observer 0,95 --radius 100", "viewshed --synthetic 1 --observer 0:0 --radius 100",
                           "viewshed --synthetic 1 --observer 0,0 --radius 0", "viewshed --synthetic 1 --observer 0,0 --radius 100 --method fast",
                           "wps", "wps http://127.0.0.1:1/wps --describe a --run b", "wps http://127.0.0.1:1/wps --run a --input nothing",
                           "wps http://127.0.0.1:1/wps --run a --bbox area=1,2,3", "wps http://127.0.0.1:1/wps --repeat 0"};
    for (const char* c : cases) {
        const CliRun r = run(c);
        EXPECT_EQ(r.exitCode, 2) << c << ": " << r.output;
        EXPECT_EQ(r.output.find("Segmentation"), std::string::npos);
    }
}

TEST(Cli, MeasureGivesGeodesicLengthsAndAreasAndNamesABadDem) {
    // A quarter of the equator: a times pi / 2; a degree square across the antimeridian.
    const CliRun quarter = run("measure --path \"0,0 90,0\"");
    EXPECT_EQ(quarter.exitCode, 0) << quarter.output;
    EXPECT_NE(quarter.output.find("length      10018.754 km over 2 points"), std::string::npos) << quarter.output;
    const CliRun square = run("measure --polygon --path \"179.5,-0.5;-179.5,-0.5;-179.5,0.5;179.5,0.5\"");
    EXPECT_EQ(square.exitCode, 0) << square.output;
    EXPECT_NE(square.output.find("(12309.2 km^2)"), std::string::npos) << square.output;
    const CliRun missing = run("measure --sight \"0,0,1 1,1,1\" --dem /nonexistent/dem.tif");
    EXPECT_EQ(missing.exitCode, 1) << missing.output;
    EXPECT_NE(missing.output.find("/nonexistent/dem.tif"), std::string::npos) << missing.output;
}

TEST(Cli, MissingSceneFileExitsOneNamingIt) {
    const CliRun r = run("render /nonexistent/scene.json -o /tmp/x.png");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("/nonexistent/scene.json: no such file"), std::string::npos) << r.output;
}

TEST(Cli, MalformedSceneExitsOneWithLine) {
    const auto file = tempFile("broken.json", "{\n \"layers\": [\n  {\"type\": \"globe\",}\n ]\n}\n");
    const CliRun r = run("render " + file.string() + " -o /tmp/x.png");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find(file.string() + ": line 3"), std::string::npos) << r.output;
}

TEST(Cli, UnknownLayerTypeExitsOne) {
    const auto file = tempFile("unknown.json", R"({"layers": [{"type": "hologram"}]})");
    const CliRun r = run("render " + file.string() + " -o /tmp/x.png");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("/layers/0/type: unknown layer type 'hologram'"), std::string::npos) << r.output;
}

TEST(Cli, BadLayerSettingExitsOne) {
    const auto file = tempFile("badsetting.json", R"({"layers": [{"type": "globe", "patchDeg": 7}]})");
    const CliRun r = run("render " + file.string() + " -o /tmp/x.png");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("/layers/0/patchDeg: must divide 180"), std::string::npos) << r.output;
}

TEST(Cli, InfoOnMissingOrUnknownFileExitsOne) {
    EXPECT_EQ(run("info /nonexistent.tif").exitCode, 1);
    const auto file = tempFile("data.xyz", "hello");
    const CliRun r = run("info " + file.string());
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("no reader"), std::string::npos);
}

TEST(Cli, InfoOnNetcdfListsVolumeVariables) {
    const std::string file = std::string(ORBIS_SOURCE_DIR) + "/../shared/data/netcdf/echam5_rectilinear_grid_3D.nc";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "no " << file << " (../shared/data is optional)";
    const CliRun r = run("info " + file);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    for (const char* s : {"\"name\": \"/t\"", "\"grid\": [", "\"vertical\": \"pressure\"", "\"lonWraps\": true"})
        EXPECT_NE(r.output.find(s), std::string::npos) << s << "\n" << r.output;
}

// Vector data: a GeoJSON written here, and North Carolina's NAD27 counties when ../shared is there.
TEST(Cli, InfoOnVectorFileListsLayers) {
    const auto file = tempFile("towns.geojson", R"({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "a", "pop": 10}, "geometry": {"type": "Point", "coordinates": [170, -40]}},
        {"type": "Feature", "properties": {"name": "b", "pop": 20}, "geometry": {"type": "Point", "coordinates": [175, -38]}}]})");
    const CliRun r = run("info " + file.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j["kind"], "vector");
    ASSERT_EQ(j["layers"].size(), 1u);
    const auto& layer = j["layers"][0];
    EXPECT_EQ(layer["name"], "towns");
    EXPECT_EQ(layer["geometryType"], "Point");
    EXPECT_EQ(layer["featureCount"], 2);
    EXPECT_EQ(layer["crs"]["epsg"], 4326);
    EXPECT_EQ(layer["fields"][1]["name"], "pop");
    EXPECT_EQ(layer["fields"][1]["type"], "Integer");
    EXPECT_NEAR(layer["extent"]["west"].get<double>(), 170.0, 1e-9);
    EXPECT_NEAR(layer["extent"]["north"].get<double>(), -38.0, 1e-9);

    const std::string nc = std::string(ORBIS_SOURCE_DIR) + "/../shared/data/vector/nc.gpkg";
    if (!std::filesystem::exists(nc)) GTEST_SKIP() << "no " << nc << " (../shared/data is optional)";
    const CliRun n = run("info " + nc);
    ASSERT_EQ(n.exitCode, 0) << n.output;
    const auto counties = nlohmann::json::parse(n.output)["layers"][0];
    EXPECT_EQ(counties["featureCount"], 100);
    EXPECT_EQ(counties["geometryType"], "Multi Polygon");
    EXPECT_EQ(counties["crs"]["name"], "NAD27");
    EXPECT_EQ(counties["crs"]["epsg"], 4267);
    // North Carolina in WGS84: 84.32 W .. 75.46 W, 33.88 N .. 36.59 N (0.01 degrees: the bounds of
    // a reprojected box, densified).
    EXPECT_NEAR(counties["extent"]["west"].get<double>(), -84.32, 0.01);
    EXPECT_NEAR(counties["extent"]["east"].get<double>(), -75.46, 0.01);
    EXPECT_NEAR(counties["extent"]["south"].get<double>(), 33.88, 0.01);
    EXPECT_NEAR(counties["extent"]["north"].get<double>(), 36.59, 0.01);
}

TEST(Cli, InfoOnSceneListsLayers) {
    const CliRun r = run(std::string("info ") + ORBIS_DEFAULT_SCENE);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("\"type\": \"terrain\""), std::string::npos) << r.output;
}

class CliGpu : public ::testing::Test {
protected:
    void SetUp() override { ASSERT_TRUE(selectLavapipe()); }
};

TEST_F(CliGpu, ViewshedOnTheGpuAgreesWithGdalAndTheExactSightLines) {
    // Generated hills, 3 km around at 30 m cells, on lavapipe: the GPU and GDAL's algorithm cell
    // for cell, both within a percent of the exact sight lines; a viewshed GeoTIFF written.
    const fs::path out = fs::temp_directory_path() / "orbis-cli-test" / "viewshed.tif";
    fs::create_directories(out.parent_path());
    const CliRun r = run("viewshed --synthetic 1 --observer 8.5,46.5 --radius 3000 --height 10 --compare --sweep --repeat 1 --device cpu --validation -o " +
                         out.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("grid        201 x 201 cells of 30.000 m"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("gpu/cpu     100.000 %"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("gpu/gdal    100.000 %"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("gpu/exact   99."), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("factor   cell_m"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::file_size(out) > 1000) << out;
    const CliRun missing = run("viewshed --dem /nonexistent/dem.tif --observer 0,0 --radius 100 --device cpu");
    EXPECT_EQ(missing.exitCode, 1) << missing.output;
    EXPECT_NE(missing.output.find("/nonexistent/dem.tif"), std::string::npos) << missing.output;
    const CliRun huge = run("viewshed --synthetic 1 --observer 0,0 --radius 1000000 --cell 10 --device cpu");
    EXPECT_EQ(huge.exitCode, 1) << huge.output;
    EXPECT_NE(huge.output.find("use larger cells"), std::string::npos) << huge.output;
}

TEST_F(CliGpu, InfoDescribesTheDevice) {
    const CliRun r = run("info --validation");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("llvmpipe"), std::string::npos);
    EXPECT_NE(r.output.find("featuresUsed"), std::string::npos);
}

TEST_F(CliGpu, RenderDefaultSceneWritesPng) {
    const fs::path out = fs::temp_directory_path() / "orbis-cli-test" / "default.png";
    fs::create_directories(out.parent_path());
    fs::remove(out);
    const CliRun r = run(std::string("render ") + ORBIS_DEFAULT_SCENE + " -o " + out.string() + " --size 160x90 --validation");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    ASSERT_TRUE(fs::exists(out));
    EXPECT_GT(fs::file_size(out), 1000u);
}

/// Renders a showcase scene of assets/scenes (its data generated at build time) with validation.
void expectShowcaseRenders(const std::string& name) {
    const fs::path out = fs::temp_directory_path() / "orbis-cli-test" / (name + ".png");
    fs::create_directories(out.parent_path());
    fs::remove(out);
    const std::string scene = std::string(ORBIS_SOURCE_DIR) + "/assets/scenes/" + name + ".json";
    const CliRun r = run("render " + scene + " -o " + out.string() + " --size 160x90 --validation");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    ASSERT_TRUE(fs::exists(out));
    EXPECT_GT(fs::file_size(out), 1000u);
}

// The FMV showcase: the fixture generated at build time, draped at the scene's current time.
TEST_F(CliGpu, RenderFmvShowcaseWritesPng) {
    expectShowcaseRenders("fmv-flight");
}

// The buildings showcase: the generated city extruded over the FMV showcase's hills.
TEST_F(CliGpu, RenderCityShowcaseWritesPng) {
    expectShowcaseRenders("vector-city");
}

// The paging showcase: a generated 2 M-vertex road network read a feature tile at a time.
TEST_F(CliGpu, RenderRoadsShowcaseWritesPng) {
    expectShowcaseRenders("vector-roads");
}

// ../shared/data/bad/: inputs that crashed Orbis or failed without naming the file or the
// problem, found by mutating real files. Each must exit 1 with a message naming the file, through
// the command that reads it; a new file there without a command here fails the test.
TEST_F(CliGpu, EveryBadFileExitsOneNamingItself) {
    const fs::path bad = fs::path(ORBIS_SOURCE_DIR) / ".." / "shared" / "data" / "bad";
    if (!fs::exists(bad)) GTEST_SKIP() << "no " << bad << " (../shared/data is optional)";
    const std::string model = jsonString(std::string(ORBIS_SOURCE_DIR) + "/assets/models/wagon.gltf");
    const std::string out = (fs::temp_directory_path() / "orbis-cli-test" / "bad.png").string();
    const std::string planet = std::string(ORBIS_SOURCE_DIR) + "/assets/scenes/synthetic-planet.json";
    auto modelScene = [&](const std::string& name, const std::string& layer) {
        return tempFile(name, R"({"orbis": 1, "viewpoint": {"lon": 0, "lat": 0, "range": 5000},
            "layers": [{"type": "model", "name": "M", )" + layer + "}]}").string();
    };
    size_t checked = 0;
    for (const auto& entry : fs::directory_iterator(bad)) {
        const std::string name = entry.path().filename().string(), file = entry.path().string();
        if (name == "README.md") continue;
        std::vector<std::string> commands;
        if (entry.path().extension() == ".gpx") {
            commands.push_back("render " + modelScene("bad-gpx.json", R"("file": )" + model + R"(, "trajectory": {"file": )" +
                                                                           jsonString(file) + "}") +
                               " -o " + out + " --size 64x36");
        } else if (entry.path().extension() == ".glb") {
            commands.push_back("render " + modelScene("bad-glb.json", R"("file": )" + jsonString(file) + R"(, "position": [0, 0, 0])") +
                               " -o " + out + " --size 64x36");
        } else if (name.starts_with("scene-")) {
            commands.push_back("info " + file);
            commands.push_back("render " + file + " -o " + out + " --size 64x36");
        } else if (name.starts_with("path-")) {
            commands.push_back("render " + planet + " -o " + out + " --size 64x36 --camera-path " + file);
        } else if (entry.path().extension() == ".nc") {
            commands.push_back("info " + file);
        } else {
            ADD_FAILURE() << name << ": no command reads this kind of file here";
        }
        for (const std::string& c : commands) {
            const CliRun r = run(c);
            EXPECT_EQ(r.exitCode, 1) << c << "\n" << r.output;
            EXPECT_NE(r.output.find(name), std::string::npos) << c << "\n" << r.output;
            EXPECT_EQ(r.output.find("json.exception"), std::string::npos) << c << "\n" << r.output;
            ++checked;
        }
    }
    EXPECT_GE(checked, 8u);
}

// A batch render whose device is lost (injected at the third submit): a clear message, exit 3,
// no hang, no crash while closing the device.
TEST_F(CliGpu, DeviceLostExitsThreeWithAClearMessage) {
    const fs::path out = fs::temp_directory_path() / "orbis-cli-test" / "lost.png";
    const CliRun r = runShell("ORBIS_FAULT_DEVICE_LOST_AFTER=3 " + std::string(ORBIS_BINARY) + " render " + ORBIS_DEFAULT_SCENE +
                              " -o " + out.string() + " --size 320x180 --device cpu");
    EXPECT_EQ(r.exitCode, 3) << r.output;
    EXPECT_NE(r.output.find("the GPU device was lost"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("VK_ERROR_DEVICE_LOST"), std::string::npos) << r.output;
}

TEST_F(CliGpu, UnwritableOutputExitsOne) {
    const CliRun r = run(std::string("render ") + ORBIS_DEFAULT_SCENE + " -o /nonexistent/dir/x.png --size 32x32");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("/nonexistent/dir/x.png"), std::string::npos) << r.output;
}

TEST_F(CliGpu, BenchPrintsJsonWithPerPassGpuTimes) {
    const CliRun r = run(std::string("bench ") + ORBIS_DEFAULT_SCENE + " --frames 3 --warmup 1 --size 160x90 --json --validation");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("\"gpu_ms\""), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\"opaque\""), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\"median\""), std::string::npos) << r.output;
}

TEST_F(CliGpu, UnknownDeviceExitsOne) {
    const CliRun r = run(std::string("render ") + ORBIS_DEFAULT_SCENE + " -o /tmp/x.png --device no-such-gpu");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("no-such-gpu"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace orbis::test

namespace orbis::test {
namespace {

TEST_F(CliGpu, BenchSweepReportsErrorAgainstRunTimeAndWritesAPlot) {
    const auto plot = std::filesystem::temp_directory_path() / "orbis-cli-sweep.png";
    std::filesystem::remove(plot);
    const CliRun r = run(std::string("bench ") + ORBIS_DEFAULT_SCENE +
                         " --sweep maxScreenSpaceError=2,16 --frames 1 --warmup 0 --size 160x120 --plot " + plot.string());
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("RMSE"), std::string::npos) << r.output;
    EXPECT_TRUE(std::filesystem::exists(plot));
    // A knob no layer has is a clear error.
    const CliRun bad = run(std::string("bench ") + ORBIS_DEFAULT_SCENE + " --sweep noSuchKnob=1,2 --frames 1 --size 64x48");
    EXPECT_EQ(bad.exitCode, 1) << bad.output;
    EXPECT_NE(bad.output.find("noSuchKnob"), std::string::npos) << bad.output;
}

TEST_F(CliGpu, BenchSetAndReferenceChangeLiveSettings) {
    // --set K=V as the viewer's panel sets it: a setting the scene's layers take runs, one no
    // layer takes is a clear error naming it, and a malformed one is a usage error.
    const CliRun r = run(std::string("bench ") + ORBIS_DEFAULT_SCENE +
                         " --set maxScreenSpaceError=8 --sweep maxScreenSpaceError=8,8 --frames 1 --warmup 0 --size 160x120 --json --plot " +
                         (std::filesystem::temp_directory_path() / "orbis-cli-set.png").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("\"rmse\": 0.0"), std::string::npos) << r.output;
    const CliRun unknown = run(std::string("bench ") + ORBIS_DEFAULT_SCENE + " --set noSuchSetting=1 --frames 1 --size 64x48");
    EXPECT_EQ(unknown.exitCode, 1) << unknown.output;
    EXPECT_NE(unknown.output.find("noSuchSetting=1"), std::string::npos) << unknown.output;
    // --reference K=V: the reference row alone has it. Two equal values of a knob give the
    // same image, unless the reference was made with another value.
    const auto rmseOfSecondRow = [&](const std::string& extra) {
        const CliRun sweep = run(std::string("bench ") + ORBIS_DEFAULT_SCENE + extra +
                                 " --sweep maxScreenSpaceError=16,16 --frames 1 --warmup 0 --size 160x120 --json --plot " +
                                 (std::filesystem::temp_directory_path() / "orbis-cli-reference.png").string());
        EXPECT_EQ(sweep.exitCode, 0) << sweep.output;
        const auto json = nlohmann::json::parse(sweep.output.substr(sweep.output.find('{')), nullptr, false);
        return json.is_discarded() ? -1.0 : json["rows"][1]["rmse"].get<double>();
    };
    EXPECT_EQ(rmseOfSecondRow(""), 0.0);
    EXPECT_GT(rmseOfSecondRow(" --reference imageryOpacity0=0"), 1.0);   // the reference without its imagery
    for (const char* bad : {"--set =1", "--set steps", "--set steps=1,2", "--set steps=x", "--reference noSuchSetting=1 --sweep steps=1,2"}) {
        const CliRun usage = run(std::string("bench ") + ORBIS_DEFAULT_SCENE + " " + bad + " --frames 1 --size 64x48");
        EXPECT_EQ(usage.exitCode, 2) << bad << ": " << usage.output;
        EXPECT_NE(usage.output.find(std::string(bad).substr(0, 5)), std::string::npos) << bad << ": " << usage.output;
    }
}

TEST_F(CliGpu, BenchIsoErrorReportsPositionErrorAgainstSteps) {
    // The sphere field's isosurface 16 (a sphere of 16 voxels), coarse and fine, with and
    // without refinement: refined hits sit on the reference's to a small fraction of a voxel;
    // unrefined ones are off by about half a step.
    const fs::path scene = tempFile("iso-error.json", R"({"viewpoint": {"lon": 0, "lat": 50, "height": 100000, "pitch": -35,
        "range": 4500000}, "layers": [{"type": "volume", "name": "Sphere", "synthetic": {"field": "sphere",
        "size": [48, 48, 48], "lon": [-10, 10], "lat": [40, 60], "height": [0, 800000]}, "mode": ["iso"], "isovalues": [16]}]})");
    const CliRun r = run("bench " + scene.string() + " --iso-error 25,100 --frames 1 --warmup 0 --size 96x72 --json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto json = nlohmann::json::parse(r.output.substr(r.output.find('{'), r.output.rfind('}') - r.output.find('{') + 1));
    ASSERT_EQ(json["rows"].size(), 4u) << r.output;
    EXPECT_EQ(json["reference_steps"], 400);
    for (const auto& row : json["rows"]) {
        const double median = row["median_voxels"].get<double>();
        if (row["refine"].get<bool>()) EXPECT_LT(median, 0.1) << row.dump();
        else EXPECT_GT(median, 0.1) << row.dump();
    }
    // Unrefined: coarser steps are further off.
    EXPECT_GT(json["rows"][0]["median_voxels"].get<double>(), json["rows"][2]["median_voxels"].get<double>());
    // A scene without an isosurface is a clear error.
    const CliRun bad = run(std::string("bench ") + ORBIS_DEFAULT_SCENE + " --iso-error 25,50 --frames 1 --size 64x48");
    EXPECT_EQ(bad.exitCode, 1) << bad.output;
    EXPECT_NE(bad.output.find("mode \"iso\""), std::string::npos) << bad.output;
}

TEST_F(CliGpu, BenchFollowsACameraPath) {
    const CliRun r = run(std::string("bench ") + ORBIS_DEFAULT_SCENE + " --camera-path " + ORBIS_SOURCE_DIR +
                         "/assets/paths/flythrough.json --frames 3 --warmup 0 --size 96x64 --json");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("\"camera_path\""), std::string::npos) << r.output;
}

}  // namespace
}  // namespace orbis::test

namespace orbis::test {
namespace {

TEST(Cli, InfoDescribesLasFiles) {
    const fs::path las = fs::temp_directory_path() / "orbis-cli-test" / "survey.las";
    fs::create_directories(las.parent_path());
    const std::string make = std::string(ORBIS_MAKE_LAS) + " --points 20000 --size 500 --out " + las.string() + " 2>&1";
    ASSERT_EQ(std::system(make.c_str()), 0);
    const CliRun r = run("info " + las.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j["kind"], "point cloud");
    EXPECT_EQ(j["points"], 20000);
    EXPECT_EQ(j["pointFormat"], 3);
    EXPECT_EQ(j["crs"]["source"], "GeoTIFF keys (EPSG:32632)");
    const double lon = j["geographicBounds"]["lon"][0].get<double>(), lat = j["geographicBounds"]["lat"][0].get<double>();
    EXPECT_NEAR(lon, 9.0, 0.01);   // the generator's area: UTM 32N around lon 9, lat 46
    EXPECT_NEAR(lat, 46.0, 0.02);
    EXPECT_EQ(j["firstPoints"].size(), 3u);

    // Not a LAS file behind a .las name; a generator usage error.
    const fs::path bad = tempFile("bad.las", "LASF but then nothing");
    const CliRun b = run("info " + bad.string());
    EXPECT_EQ(b.exitCode, 1);
    EXPECT_NE(b.output.find("bad.las"), std::string::npos) << b.output;
    EXPECT_EQ(std::system((std::string(ORBIS_MAKE_LAS) + " --points ten --out x.las > /dev/null 2>&1").c_str()) >> 8, 2);
}

}  // namespace
}  // namespace orbis::test

namespace orbis::test {
namespace {

// The real survey in ../shared/data/lidar: its CRS only in the sidecar (Oregon Lambert, feet),
// so `orbis info` places it near Eugene, Oregon; its LAZ twin next to it says how it is compressed.
TEST(Cli, InfoPlacesTheOregonSurveyAndDescribesItsLazTwin) {
    const fs::path dir = fs::path(ORBIS_SOURCE_DIR) / ".." / "shared" / "data" / "lidar";
    if (!fs::exists(dir / "1.2-with-color.las")) GTEST_SKIP() << "../shared/data is absent";
    const CliRun r = run("info " + (dir / "1.2-with-color.las").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j["version"], "1.2");
    EXPECT_EQ(j["points"], 1065);
    EXPECT_EQ(j["recordLength"], 34);
    EXPECT_EQ(j["crs"]["source"].get<std::string>().rfind("sidecar ", 0), 0u) << j["crs"];
    EXPECT_NE(j["crs"]["name"].get<std::string>().find("Oregon"), std::string::npos) << j["crs"];
    EXPECT_DOUBLE_EQ(j["crs"]["linearUnitMetres"].get<double>(), 0.3048);
    EXPECT_NEAR(j["geographicBounds"]["lon"][0].get<double>(), -123.07, 0.03);
    EXPECT_NEAR(j["geographicBounds"]["lat"][1].get<double>(), 44.06, 0.03);
    EXPECT_EQ(j["firstPoints"][0]["intensity"], 143);

    const CliRun laz = run("info " + (dir / "simple.laz").string());
    ASSERT_EQ(laz.exitCode, 0) << laz.output;
    const auto z = nlohmann::json::parse(laz.output);
    EXPECT_EQ(z["points"], 1065);
    EXPECT_EQ(z["compression"], "LAZ (LASzip 3.4r3, point-wise chunked, 1 chunk)");
    EXPECT_EQ(z["firstPoints"][0]["intensity"], 143);   // the LAS twin's first point
}

// `orbis convert`: a survey to COPC built in several batches (the progress on stderr, the
// summary naming the batches), read back by `orbis info` with every point; to LAZ and back to
// LAS; the decoding benchmark's JSON; bad arguments and outputs named.
TEST(Cli, ConvertWritesCopcInBatchesAndLaz) {
    const fs::path dir = fs::temp_directory_path() / "orbis-cli-test" / "convert";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path las = dir / "survey.las";
    ASSERT_EQ(std::system((std::string(ORBIS_MAKE_LAS) + " --points 30000 --size 500 --out " + las.string() + " 2>&1").c_str()), 0);
    const fs::path copc = dir / "survey.copc.laz";
    const CliRun c = run("convert " + las.string() + " " + copc.string() + " --node-points 200 --batch-points 10000");
    ASSERT_EQ(c.exitCode, 0) << c.output;
    EXPECT_NE(c.output.find("writing COPC"), std::string::npos) << c.output;
    EXPECT_NE(c.output.find("30000 points in"), std::string::npos) << c.output;
    EXPECT_EQ(c.output.find(" 1 batches"), std::string::npos) << c.output;
    const CliRun info = run("info " + copc.string());
    ASSERT_EQ(info.exitCode, 0) << info.output;
    const auto j = nlohmann::json::parse(info.output);
    EXPECT_EQ(j["points"], 30000);
    EXPECT_EQ(j["version"], "1.4");
    EXPECT_NE(j["compression"].get<std::string>().find("layered chunked"), std::string::npos) << j["compression"];
    for (const auto& e : fs::directory_iterator(dir)) EXPECT_NE(e.path().extension(), ".tmp") << e.path();

    const fs::path laz = dir / "survey.laz", back = dir / "back.las";
    ASSERT_EQ(run("convert " + las.string() + " " + laz.string() + " --chunk 7000").exitCode, 0);
    ASSERT_EQ(run("convert " + laz.string() + " " + back.string()).exitCode, 0);
    const auto b = nlohmann::json::parse(run("info " + back.string()).output);
    EXPECT_EQ(b["points"], 30000);
    EXPECT_EQ(b["firstPoints"], nlohmann::json::parse(run("info " + las.string()).output)["firstPoints"]);
    const CliRun d = run("convert " + laz.string() + " --decode --threads 2 --runs 1");
    ASSERT_EQ(d.exitCode, 0) << d.output;
    EXPECT_EQ(nlohmann::json::parse(d.output.substr(d.output.find('{')))["points"], 30000);

    EXPECT_EQ(run("convert " + las.string() + " " + copc.string() + " --batch-points 5").exitCode, 2);
    const CliRun t = run("convert " + las.string() + " " + (dir / "out.txt").string());
    EXPECT_EQ(t.exitCode, 2);
    EXPECT_NE(t.output.find(".laz or a .las"), std::string::npos) << t.output;
    const CliRun m = run("convert " + (dir / "missing.las").string() + " " + laz.string());
    EXPECT_EQ(m.exitCode, 1);
    EXPECT_NE(m.output.find("missing.las"), std::string::npos) << m.output;
}

// `orbis info` on 3-D models: glTF and the mesh formats, as the model layer reads them.
TEST(Cli, InfoDescribesModels) {
    const CliRun wagon = run(std::string("info ") + ORBIS_SOURCE_DIR + "/assets/models/wagon.gltf");
    ASSERT_EQ(wagon.exitCode, 0) << wagon.output;
    const auto w = nlohmann::json::parse(wagon.output);
    EXPECT_EQ(w["kind"], "3-D model");
    EXPECT_EQ(w["reader"], "glTF");
    EXPECT_GT(w["triangles"].get<int>(), 0);
    const fs::path duck = "/usr/share/assimp/models/Collada/duck.dae";
    if (fs::exists(duck)) {
        const CliRun d = run("info " + duck.string());
        ASSERT_EQ(d.exitCode, 0) << d.output;
        const auto j = nlohmann::json::parse(d.output);
        EXPECT_EQ(j["reader"], "Assimp");
        EXPECT_EQ(j["textures"][0]["width"], 512);
        EXPECT_NEAR(j["sizeMetres"][1].get<double>(), 1.54, 0.01);   // upright, as drawn
        EXPECT_TRUE(j["warnings"].empty());
    }
    const fs::path bad = tempFile("huge.ply", "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n1\n");
    const CliRun b = run("info " + bad.string());
    EXPECT_EQ(b.exitCode, 1);
    EXPECT_NE(b.output.find("huge.ply: its header claims 4000000000 vertex elements"), std::string::npos) << b.output;
}

// A LAS signature with a header from no known version: exit 1, the file and the problem named.
TEST(Cli, InfoNamesABadLasHeader) {
    const fs::path bad = tempFile("version-zero.las", std::string("LASF").append(400, '\0'));
    const CliRun r = run("info " + bad.string());
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("version-zero.las: LAS version 0.0 is not supported"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace orbis::test

namespace orbis::test {
namespace {

/// The JSON objects of `output`, one a line (lines that are not JSON, such as the stderr
/// summary, are left out).
std::vector<nlohmann::json> jsonLines(const std::string& output) {
    std::vector<nlohmann::json> lines;
    std::size_t pos = 0;
    while (pos < output.size()) {
        const std::size_t end = std::min(output.find('\n', pos), output.size());
        const std::string line = output.substr(pos, end - pos);
        if (!line.empty() && line[0] == '{') lines.push_back(nlohmann::json::parse(line));
        pos = end + 1;
    }
    return lines;
}

// The two real ST 0601 packets: one JSON line each, with the checksum verdict; the wrong one is
// also summed up on stderr.
TEST(Cli, InfoPrintsKlvPacketsAsJsonLines) {
    const fs::path dir = fs::path(ORBIS_SOURCE_DIR) / ".." / "shared" / "data" / "klv";
    if (!fs::exists(dir / "DynamicOnlyMISMMSPacketData.bin")) GTEST_SKIP() << "../shared/data is absent";
    const CliRun good = run("info " + (dir / "DynamicOnlyMISMMSPacketData.bin").string());
    ASSERT_EQ(good.exitCode, 0) << good.output;
    const auto lines = jsonLines(good.output);
    ASSERT_EQ(lines.size(), 1u) << good.output;
    EXPECT_EQ(lines[0]["offset"], 0);
    EXPECT_EQ(lines[0]["checksum"]["verdict"], "valid");
    EXPECT_NEAR(lines[0]["sensorLatitudeDeg"].get<double>(), 60.1768, 1e-4);
    EXPECT_NEAR(lines[0]["sensorLongitudeDeg"].get<double>(), 128.4268, 1e-4);
    EXPECT_NEAR(lines[0]["platformHeadingDeg"].get<double>(), 159.97, 1e-2);

    const CliRun bad = run("info " + (dir / "DynamicConstantMISMMSPacketData.bin").string());
    ASSERT_EQ(bad.exitCode, 0) << bad.output;
    const auto badLines = jsonLines(bad.output);
    ASSERT_EQ(badLines.size(), 1u) << bad.output;
    EXPECT_EQ(badLines[0]["checksum"]["verdict"], "mismatch");
    EXPECT_EQ(badLines[0]["checksum"]["stored"], "aa43");
    EXPECT_EQ(badLines[0]["otherTags"][0]["tag"], 48);   // the nested ST 0102 security set, raw
    EXPECT_NE(bad.output.find("1 with a wrong checksum"), std::string::npos) << bad.output;
}

TEST(Cli, InfoOnBrokenKlvExitsOneAndReadsPoseCsv) {
    const auto garbage = tempFile("garbage.klv", "no key in here at all");
    const CliRun g = run("info " + garbage.string());
    EXPECT_EQ(g.exitCode, 1) << g.output;
    EXPECT_NE(g.output.find(garbage.string() + ": no MISB ST 0601 packet"), std::string::npos) << g.output;
    // The key, then a 9-byte BER length: the packet is found and cannot be decoded.
    const std::string key("\x06\x0E\x2B\x34\x02\x0B\x01\x01\x0E\x01\x03\x01\x01\x00\x00\x00", 16);
    const auto broken = tempFile("broken.bin", key + "\x89" + std::string(12, '\x01'));
    const CliRun b = run("info " + broken.string());
    EXPECT_EQ(b.exitCode, 1) << b.output;
    EXPECT_NE(b.output.find("long form of 9 bytes"), std::string::npos) << b.output;
    EXPECT_NE(b.output.find(broken.string() + ": none of its 1 ST 0601 packets decodes"), std::string::npos) << b.output;

    const auto pose = tempFile("pose.csv", "time,lat,lon,alt,heading\n0,48.5,11.25,1000,90\n0.5,48.6,11.3,1001,91\n");
    const CliRun p = run("info " + pose.string());
    ASSERT_EQ(p.exitCode, 0) << p.output;
    const auto rows = jsonLines(p.output);
    ASSERT_EQ(rows.size(), 2u) << p.output;
    EXPECT_EQ(rows[1]["line"], 3);
    EXPECT_EQ(rows[1]["precisionTimeUs"], 500000);
    EXPECT_EQ(rows[1]["platformHeadingDeg"], 91.0);
    const auto badPose = tempFile("badpose.csv", "time,lat,lon,alt\n0,north,11,1\n");
    const CliRun bp = run("info " + badPose.string());
    EXPECT_EQ(bp.exitCode, 1) << bp.output;
    EXPECT_NE(bp.output.find("badpose.csv: line 2, column 2 (lat): 'north' is not a number"), std::string::npos) << bp.output;
}

}  // namespace
}  // namespace orbis::test

namespace orbis::test {
namespace {

// The FMV fixture: orbis-make-fmv writes the synthetic flight's DEM, MPEG-TS and pose CSV;
// `orbis info` describes the video stream and prints each KLV packet with its time.
TEST(Cli, InfoDescribesAVideoAndItsKlvPackets) {
    const fs::path dir = fs::temp_directory_path() / "orbis-cli-test" / "fmv";
    fs::remove_all(dir);
    const std::string make = std::string(ORBIS_MAKE_FMV) + " " + dir.string() + " --frames 15 --size 320x240 --csv > /dev/null 2>&1";
    ASSERT_EQ(std::system(make.c_str()), 0);
    for (const char* f : {"flight.ts", "flight-dem.tif", "flight.csv"}) EXPECT_TRUE(fs::exists(dir / f)) << f;
    const CliRun r = run("info " + (dir / "flight.ts").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::istringstream lines(r.output);
    std::string line;
    ASSERT_TRUE(std::getline(lines, line));
    const auto video = nlohmann::json::parse(line)["video"];
    EXPECT_EQ(video["codec"], "h264");
    EXPECT_EQ(video["width"], 320);
    EXPECT_EQ(video["frames"], 15);
    EXPECT_EQ(video["klvPackets"], 15);
    int packets = 0;
    while (std::getline(lines, line)) {
        const auto p = nlohmann::json::parse(line);
        EXPECT_NEAR(p["time"].get<double>(), 0.1 * packets, 1e-6);
        EXPECT_EQ(p["checksum"]["verdict"], "valid");
        EXPECT_EQ(p["missionId"], "ORBIS SYNTHETIC");
        EXPECT_NEAR(p["horizontalFovDeg"].get<double>(), 24.0, 0.01);
        ++packets;
    }
    EXPECT_EQ(packets, 15);
    // The CSV sidecar of the same poses reads as a pose CSV.
    const CliRun csv = run("info " + (dir / "flight.csv").string());
    EXPECT_EQ(csv.exitCode, 0) << csv.output;
    // Not a video behind a .ts name; a generator usage error.
    const fs::path bad = tempFile("bad.ts", "not a transport stream at all");
    const CliRun b = run("info " + bad.string());
    EXPECT_EQ(b.exitCode, 1);
    EXPECT_NE(b.output.find("bad.ts"), std::string::npos) << b.output;
    EXPECT_EQ(std::system((std::string(ORBIS_MAKE_FMV) + " " + dir.string() + " --frames none > /dev/null 2>&1").c_str()) >> 8, 2);
}

// `orbis bench --poses` times each animation's poses of a glTF model on the CPU.
TEST(Cli, BenchPosesTimesEveryAnimation) {
    const fs::path arm = tempFile("arm.gltf", twoJointArmGltf());
    const CliRun r = run("bench --poses " + arm.string());
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("1 skins (2 joints), 1 animations"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("Bend"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("us/pose"), std::string::npos) << r.output;
    const CliRun broken = run("bench --poses " + tempFile("broken.gltf", "{").string());
    EXPECT_EQ(broken.exitCode, 1);
    EXPECT_NE(broken.output.find("broken.gltf"), std::string::npos) << broken.output;
    EXPECT_EQ(run("bench --poses " + arm.string() + " scene.json").exitCode, 2);
}

}  // namespace
}  // namespace orbis::test
