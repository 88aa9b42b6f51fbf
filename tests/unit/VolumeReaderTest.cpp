// The netCDF volume reader: CF axes in any order, packing, fill values, groups, pressure levels,
// longitudes across the antimeridian, time, and bad inputs. Fixtures are written at test time
// with GDAL's multidimensional netCDF writer; real files from ../shared/data when present.
#include "layers/volume/VolumeReader.h"

#include "tests/support/NetcdfWriter.h"
#include "tests/support/ProcessTempDir.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace orbis::layers {
namespace {

namespace fs = std::filesystem;

fs::path tempDir() {
    static const fs::path p = [] {
        fs::path d = orbis::test::processTempDir("orbis-volume-test");
        return d;
    }();
    return p;
}

struct TempCleanup : ::testing::Environment {
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(tempDir(), ec);
    }
};
[[maybe_unused]] auto* const gCleanup = ::testing::AddGlobalTestEnvironment(new TempCleanup);

using Dim = test::NcDim;
using Variable = test::NcVariable;

void writeNc(const fs::path& file, const std::vector<Dim>& dims, const Variable& var,
             const std::function<double(const std::vector<size_t>&)>& value) {
    ASSERT_EQ(test::writeNetcdf(file, dims, var, value), "");
}

Dim lonDim(std::vector<double> v) { return test::ncLon(std::move(v)); }
Dim latDim(std::vector<double> v) { return test::ncLat(std::move(v)); }
Dim presDim(std::vector<double> v, const char* units = "Pa") { return test::ncPressure(std::move(v), units); }
Dim timeDim(std::vector<double> v) { return test::ncTime(std::move(v)); }

// The analytic field: separable, so a misplaced axis or flip shows at once.
double field(double lon, double lat, double level, double time) { return lon + 1000.0 * lat + 0.01 * level + 1e6 * time; }

Result<VolumeField> read(const fs::path& file, const std::string& variable = "t", size_t timeIndex = 0) {
    VolumeReadOptions o;
    o.path = file.string();
    o.variable = variable;
    o.timeIndex = timeIndex;
    return readVolume(o);
}

}  // namespace

TEST(StandardAtmosphere, MatchesTheTableAndRoundTrips) {
    EXPECT_NEAR(standardAtmosphereHeight(101325.0), 0.0, 1e-6);
    EXPECT_NEAR(standardAtmosphereHeight(22632.06), 11000.0, 0.1);
    EXPECT_NEAR(standardAtmosphereHeight(5474.889), 20000.0, 0.1);
    EXPECT_NEAR(standardAtmosphereHeight(868.0187), 32000.0, 0.1);
    EXPECT_NEAR(standardAtmosphereHeight(110.9063), 47000.0, 0.5);
    EXPECT_NEAR(standardAtmosphereHeight(50000.0), 5574.0, 2.0);   // 500 hPa
    EXPECT_NEAR(standardAtmosphereHeight(100.0), 47856.0, 50.0);   // 1 hPa (ECHAM5's top levels)
    for (double p : {105000.0, 101325.0, 85000.0, 30000.0, 9000.0, 1000.0, 100.0, 10.0, 1.0})
        EXPECT_NEAR(standardAtmospherePressure(standardAtmosphereHeight(p)), p, p * 1e-9) << p;
    // Monotonic: higher pressure, lower height.
    double last = 1e9;
    for (double p = 1.0; p < 110000.0; p *= 1.3) {
        const double h = standardAtmosphereHeight(p);
        EXPECT_LT(h, last) << p;
        last = h;
    }
}

TEST(CfTime, UnitsWithReferenceDates) {
    auto a = parseCfTimeUnits("hours since 2001-01-01 00:00:00");
    ASSERT_TRUE(a.ok()) << a.message();
    EXPECT_EQ(a->secondsPerUnit, 3600.0);
    EXPECT_EQ(formatIso8601(a->reference, 0), "2001-01-01T00:00:00Z");
    auto b = parseCfTimeUnits("days since 1970-1-1");
    ASSERT_TRUE(b.ok()) << b.message();
    EXPECT_EQ(b->reference, 0);
    EXPECT_EQ(b->secondsPerUnit, 86400.0);
    auto c = parseCfTimeUnits("seconds since 2020-02-29T12:30:15Z");
    ASSERT_TRUE(c.ok()) << c.message();
    EXPECT_EQ(formatIso8601(c->reference, 0), "2020-02-29T12:30:15Z");
    EXPECT_FALSE(parseCfTimeUnits("Month").ok());
    EXPECT_NE(parseCfTimeUnits("months since 2000-01-01").message().find("months and years"), std::string::npos);
    EXPECT_FALSE(parseCfTimeUnits("days since yesterday").ok());
}

TEST(VolumeReader, PlacesAxesFlipsThemAndConvertsPressure) {
    // File order (time, lev, lat, lon); latitudes north to south and uneven (Gaussian-like);
    // pressures from the ground up; longitudes 0..315.
    const std::vector<double> lons{0, 45, 90, 135, 180, 225, 270, 315}, lats{80, 41.5, 0.0, -41.5, -80};
    const std::vector<double> levs{100000, 50000, 10000}, times{6, 12};
    const fs::path file = tempDir() / "basic.nc";
    Variable v;
    v.attrs = {{"units", "K"}, {"long_name", "temperature"}};
    writeNc(file, {timeDim(times), presDim(levs), latDim(lats), lonDim(lons)}, v, [&](const std::vector<size_t>& i) {
        return field(lons[i[3]], lats[i[2]], levs[i[1]], double(i[0]));
    });
    auto f = read(file, "t", 1);
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ(f->variable, "/t");
    EXPECT_EQ(f->units, "K");
    EXPECT_EQ(f->longName, "temperature");
    ASSERT_EQ(f->nx(), 8u);
    ASSERT_EQ(f->ny(), 5u);
    ASSERT_EQ(f->nz(), 3u);
    EXPECT_TRUE(f->lonWraps);
    EXPECT_EQ(f->lonDeg.front(), 0.0);
    EXPECT_EQ(f->lonDeg.back(), 315.0);
    EXPECT_EQ(f->latDeg.front(), -80.0);   // ascending
    EXPECT_EQ(f->latDeg[1], -41.5);
    EXPECT_EQ(f->verticalSource, VerticalSource::Pressure);
    EXPECT_NEAR(f->heightM[0], standardAtmosphereHeight(100000), 1e-9);
    EXPECT_NEAR(f->heightM[2], standardAtmosphereHeight(10000), 1e-9);
    EXPECT_EQ(f->verticalRaw[0], 100000.0);
    ASSERT_EQ(f->times.size(), 2u);
    EXPECT_EQ(formatIso8601(f->times[1], 0), "2001-01-01T12:00:00Z");
    EXPECT_EQ(f->timeSteps, 2u);
    EXPECT_EQ(f->timeIndex, 1u);
    for (size_t k = 0; k < 3; ++k)
        for (size_t j = 0; j < 5; ++j)
            for (size_t i = 0; i < 8; ++i)
                ASSERT_FLOAT_EQ(f->at(i, j, k), float(field(f->lonDeg[i], f->latDeg[j], f->verticalRaw[k], 1.0)))
                    << i << " " << j << " " << k;
    EXPECT_EQ(f->validCount, 120u);
    EXPECT_FLOAT_EQ(f->minValue, float(field(0, -80, 10000, 1)));
    EXPECT_FLOAT_EQ(f->maxValue, float(field(315, 80, 100000, 1)));
}

TEST(VolumeReader, AnyDimensionOrderGivesTheSameField) {
    const std::vector<double> lons{-20, -10, 0, 10}, lats{10, 20, 30}, heights{0, 1000, 5000};
    const Dim h{"z", heights, {{"units", "m"}, {"positive", "up"}}};
    const fs::path a = tempDir() / "order-a.nc", b = tempDir() / "order-b.nc";
    writeNc(a, {lonDim(lons), latDim(lats), h}, {}, [&](const std::vector<size_t>& i) {
        return field(lons[i[0]], lats[i[1]], heights[i[2]], 0);
    });
    writeNc(b, {h, timeDim({0}), lonDim(lons), latDim(lats)}, {}, [&](const std::vector<size_t>& i) {
        return field(lons[i[2]], lats[i[3]], heights[i[0]], 0);
    });
    auto fa = read(a), fb = read(b);
    ASSERT_TRUE(fa.ok()) << fa.message();
    ASSERT_TRUE(fb.ok()) << fb.message();
    EXPECT_EQ(fa->values, fb->values);
    EXPECT_EQ(fa->heightM, heights);
    EXPECT_FALSE(fa->lonWraps);
    EXPECT_TRUE(fa->times.empty());
    EXPECT_FLOAT_EQ(fa->at(3, 2, 1), float(field(10, 30, 1000, 0)));
}

TEST(VolumeReader, DepthsBecomeNegativeHeightsAndKilometresMetres) {
    const std::vector<double> lons{0, 1}, lats{0, 1}, depths{0, 10, 250};
    const fs::path a = tempDir() / "depth.nc", b = tempDir() / "km.nc";
    writeNc(a, {{"depth", depths, {{"units", "m"}, {"positive", "down"}}}, latDim(lats), lonDim(lons)}, {},
            [&](const std::vector<size_t>& i) { return double(i[0]); });
    writeNc(b, {{"alt", {0.5, 1.5}, {{"units", "km"}, {"axis", "Z"}}}, latDim(lats), lonDim(lons)}, {},
            [&](const std::vector<size_t>& i) { return double(i[0]); });
    auto fa = read(a), fb = read(b);
    ASSERT_TRUE(fa.ok()) << fa.message();
    ASSERT_TRUE(fb.ok()) << fb.message();
    EXPECT_EQ(fa->verticalSource, VerticalSource::Depth);
    EXPECT_EQ(fa->heightM, (std::vector<double>{-250, -10, 0}));
    EXPECT_EQ(fa->at(0, 0, 0), 2.0f);   // the deepest level comes first
    EXPECT_EQ(fb->heightM, (std::vector<double>{500, 1500}));
}

namespace {

/// A (time, lev, lat, lon) file of the analytic field with the given axes.
void writeTimed(const fs::path& file, const std::vector<double>& lons, const std::vector<double>& lats,
                const std::vector<double>& levs, const std::vector<double>& times) {
    writeNc(file, {timeDim(times), presDim(levs), latDim(lats), lonDim(lons)}, {}, [&](const std::vector<size_t>& i) {
        return field(lons[i[3]], lats[i[2]], levs[i[1]], double(i[0]));
    });
}

}  // namespace

// Reading every time step at once gives what reading each step alone gives, with the range over
// all of them.
TEST(VolumeReader, AllTimeStepsAreEachStepInOrder) {
    const fs::path file = tempDir() / "steps.nc";
    writeTimed(file, {0, 10, 20}, {-5, 5}, {100000, 50000}, {0, 6, 12});
    VolumeReadOptions o;
    o.path = file.string();
    o.variable = "t";
    auto all = readVolumeTimeSteps(o);
    ASSERT_TRUE(all.ok()) << all.message();
    ASSERT_EQ(all->more.size(), 2u);
    EXPECT_EQ(all->field.timeIndex, 0u);
    size_t valid = 0;
    for (size_t s = 0; s < 3; ++s) {
        auto one = read(file, "t", s);
        ASSERT_TRUE(one.ok()) << one.message();
        EXPECT_EQ(s == 0 ? all->field.values : all->more[s - 1], one->values) << "step " << s;
        valid += one->validCount;
        if (s == 0) {
            EXPECT_EQ(all->field.minValue, one->minValue);
        }
        if (s == 2) {
            EXPECT_EQ(all->field.maxValue, one->maxValue);
        }
    }
    EXPECT_EQ(all->field.validCount, valid);
    // Asked to read one step only: that step, as readVolume reads it.
    o.timeIndex = 1;
    auto one = readVolumeTimeSteps(o, [](const VolumeField& grid) -> Result<bool> {
        EXPECT_TRUE(grid.values.empty()) << "the decision comes before any value is read";
        EXPECT_EQ(grid.timeSteps, 3u);
        return false;
    });
    ASSERT_TRUE(one.ok()) << one.message();
    EXPECT_TRUE(one->more.empty());
    EXPECT_EQ(one->field.timeIndex, 1u);
    EXPECT_EQ(one->field.values, all->more[0]);
    // Refused (a budget): the refusal is the error.
    auto refused = readVolumeTimeSteps(o, [](const VolumeField&) -> Result<bool> { return makeError("too big"); });
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.message(), "too big");
}

// Issue 23: a file replaced on disk (renamed over, as tools write) while its time steps are read.
// The steps all come from the file that was opened, on its grid; the new file shows on the next
// open. Before, each step opened the file again and a step of another grid joined the others.
TEST(VolumeReader, AFileReplacedWhileItsTimeStepsAreReadIsNotMixedIn) {
    const fs::path file = tempDir() / "replaced.nc", other = tempDir() / "replacement.nc";
    const std::vector<double> lons{0, 10, 20, 30}, lats{-5, 0, 5}, levs{100000, 50000};
    writeTimed(file, lons, lats, levs, {0, 6, 12});
    writeTimed(other, {0, 5, 10, 15, 20}, {-8, -4, 0, 4, 8}, {100000, 70000, 50000}, {0, 6, 12, 18});
    VolumeReadOptions o;
    o.path = file.string();
    o.variable = "t";
    bool replaced = false;
    auto all = readVolumeTimeSteps(o, [&](const VolumeField&) -> Result<bool> {
        std::error_code ec;
        fs::rename(other, file, ec);
        replaced = !ec;
        return true;
    });
    ASSERT_TRUE(replaced);
    ASSERT_TRUE(all.ok()) << all.message();
    const VolumeField& f = all->field;
    ASSERT_EQ(f.nx(), 4u);
    ASSERT_EQ(f.ny(), 3u);
    ASSERT_EQ(f.nz(), 2u);
    ASSERT_EQ(all->more.size(), 2u);
    for (size_t s = 0; s < 3; ++s) {
        const std::vector<float>& values = s == 0 ? f.values : all->more[s - 1];
        ASSERT_EQ(values.size(), f.values.size()) << "step " << s;
        for (size_t k = 0; k < 2; ++k)
            for (size_t j = 0; j < 3; ++j)
                for (size_t i = 0; i < 4; ++i)
                    ASSERT_FLOAT_EQ(values[(k * 3 + j) * 4 + i],
                                    float(field(f.lonDeg[i], f.latDeg[j], f.verticalRaw[k], double(s))))
                        << "step " << s << " at " << i << " " << j << " " << k;
    }
    auto now = read(file);   // the next open reads the new file
    ASSERT_TRUE(now.ok()) << now.message();
    EXPECT_EQ(now->nx(), 5u);
    EXPECT_EQ(now->timeSteps, 4u);
}

TEST(VolumeReader, LongitudesAcrossTheAntimeridianStayContinuous) {
    const std::vector<double> lons{170, 175, 180, -175, -170}, lats{-5, 5}, levs{1000, 500};
    const fs::path file = tempDir() / "antimeridian.nc";
    writeNc(file, {presDim(levs, "hPa"), latDim(lats), lonDim(lons)}, {},
            [&](const std::vector<size_t>& i) { return lons[i[2]]; });
    auto f = read(file);
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ(f->lonDeg, (std::vector<double>{170, 175, 180, 185, 190}));
    EXPECT_FALSE(f->lonWraps);
    EXPECT_EQ(f->at(3, 0, 0), -175.0f);   // the value stays the file's
    EXPECT_NEAR(f->heightM[0], standardAtmosphereHeight(100000.0), 1e-9);   // hPa

    // Descending from 180 to -180 (a closing duplicate point): ascending, wrapping.
    const fs::path file2 = tempDir() / "descending.nc";
    std::vector<double> desc;
    for (double l = 180; l >= -180; l -= 90) desc.push_back(l);
    writeNc(file2, {presDim(levs, "hPa"), latDim(lats), lonDim(desc)}, {}, [&](const std::vector<size_t>& i) {
        return desc[i[2]];
    });
    auto g = read(file2);
    ASSERT_TRUE(g.ok()) << g.message();
    EXPECT_EQ(g->lonDeg, (std::vector<double>{-180, -90, 0, 90, 180}));
    EXPECT_TRUE(g->lonWraps);
    EXPECT_EQ(g->at(1, 0, 0), -90.0f);
}

TEST(VolumeReader, PackingFillMissingAndValidRangeBecomeNoData) {
    const std::vector<double> lons{0, 1, 2, 3}, lats{0, 1}, levs{1000, 850};
    const fs::path file = tempDir() / "packed.nc";
    Variable v;
    v.type = GDT_Int16;
    v.noData = -32767;
    v.scale = 0.5;
    v.offset = 200.0;
    v.numericAttrs = {{"missing_value", {-32000}}, {"valid_range", {-1000, 1000}}};
    writeNc(file, {presDim(levs, "hPa"), latDim(lats), lonDim(lons)}, v, [&](const std::vector<size_t>& i) {
        const size_t n = (i[0] * 2 + i[1]) * 4 + i[2];
        if (n == 0) return -32767.0;   // fill
        if (n == 1) return -32000.0;   // missing
        if (n == 2) return 5000.0;     // outside valid_range
        return double(n) * 10.0;       // packed
    });
    auto f = read(file);
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_TRUE(std::isnan(f->at(0, 0, 0)));
    EXPECT_TRUE(std::isnan(f->at(1, 0, 0)));
    EXPECT_TRUE(std::isnan(f->at(2, 0, 0)));
    EXPECT_FLOAT_EQ(f->at(3, 0, 0), 3 * 10 * 0.5f + 200.0f);
    EXPECT_EQ(f->validCount, 13u);
    EXPECT_FLOAT_EQ(f->minValue, 30 * 0.5f + 200.0f);
    EXPECT_FLOAT_EQ(f->maxValue, 150 * 0.5f + 200.0f);
}

TEST(VolumeReader, AllFillAndConstantFieldsAreReadable) {
    const std::vector<double> lons{0, 1}, lats{0, 1}, levs{1000, 500};
    const fs::path fill = tempDir() / "allfill.nc", constant = tempDir() / "constant.nc";
    Variable v;
    v.noData = -999.0;
    writeNc(fill, {presDim(levs, "hPa"), latDim(lats), lonDim(lons)}, v, [](const std::vector<size_t>&) { return -999.0; });
    writeNc(constant, {presDim(levs, "hPa"), latDim(lats), lonDim(lons)}, v, [](const std::vector<size_t>&) { return 7.0; });
    auto f = read(fill);
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ(f->validCount, 0u);
    EXPECT_EQ(f->minValue, 0.0f);
    EXPECT_EQ(f->maxValue, 0.0f);
    auto c = read(constant);
    ASSERT_TRUE(c.ok()) << c.message();
    EXPECT_EQ(c->minValue, 7.0f);
    EXPECT_EQ(c->maxValue, 7.0f);
}

TEST(VolumeReader, VariablesInGroups) {
    const std::vector<double> lons{0, 1}, lats{0, 1}, levs{1000, 500};
    const fs::path file = tempDir() / "groups.nc";
    Variable v;
    v.group = "grp1";
    v.name = "T";
    writeNc(file, {presDim(levs, "hPa"), latDim(lats), lonDim(lons)}, v, [](const std::vector<size_t>& i) {
        return double(i[2]);
    });
    auto byName = read(file, "T");
    ASSERT_TRUE(byName.ok()) << byName.message();
    EXPECT_EQ(byName->variable, "/grp1/T");
    auto byPath = read(file, "/grp1/T");
    ASSERT_TRUE(byPath.ok()) << byPath.message();
    EXPECT_EQ(byPath->values, byName->values);
}

TEST(VolumeReader, BadInputsGiveClearErrors) {
    const std::vector<double> lons{0, 1}, lats{0, 1}, levs{1000, 500};
    const auto fieldOf = [](const std::vector<size_t>&) { return 1.0; };
    const auto expectError = [](const Result<VolumeField>& r, const std::string& what) {
        SCOPED_TRACE(what);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.message().find(what), std::string::npos) << r.message();
    };
    expectError(read(tempDir() / "missing.nc"), "no such file");

    const fs::path good = tempDir() / "good.nc";
    writeNc(good, {presDim(levs, "hPa"), latDim(lats), lonDim(lons)}, {}, fieldOf);
    expectError(read(good, "nothing"), "no variable \"nothing\" (volume variables: /t)");
    expectError(read(good, "lat"), "has 1 dimension(s)");
    VolumeReadOptions small;
    small.path = good.string();
    small.variable = "t";
    small.maxBytes = 16;
    expectError(readVolume(small), "more than the budget");
    const fs::path timed = tempDir() / "timed.nc";
    writeNc(timed, {timeDim({0, 6}), presDim(levs, "hPa"), latDim(lats), lonDim(lons)}, {}, fieldOf);
    expectError(read(timed, "t", 3), "time step 3 does not exist (2 steps)");

    const fs::path flat = tempDir() / "flat.nc";
    writeNc(flat, {latDim(lats), lonDim(lons)}, {}, fieldOf);
    expectError(read(flat), "has 2 dimension(s)");

    const fs::path extra = tempDir() / "extra.nc";
    writeNc(extra, {{"member", {1, 2}, {}}, presDim(levs, "hPa"), latDim(lats), lonDim(lons)}, {}, fieldOf);
    expectError(read(extra), "cannot place dimension \"member\"");

    const fs::path noVertical = tempDir() / "novertical.nc";
    writeNc(noVertical, {{"band", {1, 2, 3}, {}}, latDim(lats), lonDim(lons)}, {}, fieldOf);
    expectError(read(noVertical), "cannot place dimension \"band\"");

    const fs::path badUnits = tempDir() / "badunits.nc";
    writeNc(badUnits, {{"lev", levs, {{"units", "sigma"}, {"axis", "Z"}}}, latDim(lats), lonDim(lons)}, {}, fieldOf);
    expectError(read(badUnits), "neither a pressure");

    const fs::path corrupt = tempDir() / "corrupt.nc";
    {
        std::ifstream in(good, std::ios::binary);
        std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
        std::ofstream out(corrupt, std::ios::binary);
        out.write(bytes.data(), std::streamsize(std::min<size_t>(bytes.size(), 200)));
    }
    const auto r = read(corrupt);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.message().find(corrupt.string()), std::string::npos) << r.message();

    const fs::path text = tempDir() / "text.nc";
    std::ofstream(text) << "not netCDF\n";
    expectError(read(text), "not a multidimensional file GDAL can read");
}

TEST(VolumeReader, DescribeListsVariablesAxesAndRanges) {
    const std::vector<double> lons{0, 1}, lats{0, 1}, levs{1000, 500};
    const fs::path file = tempDir() / "describe.nc";
    Variable v;
    v.attrs = {{"units", "K"}};
    writeNc(file, {timeDim({0, 6}), presDim(levs, "hPa"), latDim(lats), lonDim(lons)}, v,
            [](const std::vector<size_t>& i) { return 250.0 + double(i[3]); });
    auto json = describeVolumeJson(file.string());
    ASSERT_TRUE(json.ok()) << json.message();
    for (const char* s : {"\"name\": \"/t\"", "\"axis\": \"vertical\"", "\"axis\": \"time\"", "\"readable\": true",
                          "\"grid\": [", "\"vertical\": \"pressure\"", "\"timeSteps\": 2", "2001-01-01T06:00:00Z"})
        EXPECT_NE(json->find(s), std::string::npos) << s << "\n" << *json;
    EXPECT_TRUE(looksLikeVolumeFile(file.string()));
    EXPECT_FALSE(describeVolumeJson((tempDir() / "none.nc").string()).ok());
}

// An attribute in another encoding (Latin-1's 0xB0 for the degree sign) is shown with U+FFFD
// and named, where nlohmann's dump threw a type_error naming neither the file nor the attribute
// (../shared/data/bad/nc-units-non-utf8.nc). Well-formed UTF-8 ("°C") is no problem.
TEST(VolumeReader, DescribeNamesTextThatIsNotUtf8) {
    const std::vector<double> lons{0, 1}, lats{0, 1}, levs{1000, 500};
    const fs::path file = tempDir() / "latin1.nc";
    Variable v;
    v.attrs = {{"units", "\xB0" "C"}, {"long_name", "temp\xC3\xA9rature \xC3"}};
    writeNc(file, {presDim(levs, "hPa"), latDim(lats), lonDim(lons)}, v, [](const std::vector<size_t>&) { return 1.0; });
    std::vector<std::string> problems;
    auto json = describeVolumeJson(file.string(), &problems);
    ASSERT_TRUE(json.ok()) << json.message();
    EXPECT_NE(json->find("\"units\": \"\xEF\xBF\xBD" "C\""), std::string::npos) << *json;
    ASSERT_EQ(problems.size(), 2u);
    EXPECT_EQ(problems[0], file.string() + ": /t longName: byte 0xC3 at 13 is not UTF-8 (shown as U+FFFD)");
    EXPECT_EQ(problems[1], file.string() + ": /t units: byte 0xB0 at 0 is not UTF-8 (shown as U+FFFD)");

    const fs::path good = tempDir() / "utf8.nc";
    v.attrs = {{"units", "\xC2\xB0" "C"}, {"long_name", "\xE6\xB8\xA9\xE5\xBA\xA6 \xF0\x9F\x8C\xA1"}};
    writeNc(good, {presDim(levs, "hPa"), latDim(lats), lonDim(lons)}, v, [](const std::vector<size_t>&) { return 1.0; });
    problems.clear();
    ASSERT_TRUE(describeVolumeJson(good.string(), &problems).ok());
    EXPECT_TRUE(problems.empty()) << problems.front();
}

// ---------------------------------------------------------------------------------------------
// Real files (../shared/data/netcdf), skipped when absent

TEST(VolumeReaderRealData, Echam5TemperatureOnPressureLevels) {
    const fs::path file = fs::path(ORBIS_SHARED_DATA_DIR) / "netcdf/echam5_rectilinear_grid_3D.nc";
    if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
    auto f = read(file, "t");
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ(f->nx(), 192u);
    EXPECT_EQ(f->ny(), 96u);
    EXPECT_EQ(f->nz(), 17u);
    EXPECT_TRUE(f->lonWraps);
    EXPECT_NEAR(f->lonDeg.front(), -180.0, 1e-9);
    EXPECT_LT(f->latDeg.front(), -88.0);   // Gaussian: the first latitude is not -90
    EXPECT_GT(f->latDeg.front(), -89.5);
    EXPECT_EQ(f->verticalSource, VerticalSource::Pressure);
    EXPECT_LT(f->heightM.front(), 200.0);    // 1000 hPa
    EXPECT_GT(f->heightM.back(), 30000.0);   // 10 hPa
    EXPECT_EQ(f->validCount, f->values.size());
    EXPECT_GT(f->minValue, 170.0f);   // K
    EXPECT_LT(f->maxValue, 320.0f);
    ASSERT_EQ(f->times.size(), 1u);
}

TEST(VolumeReaderRealData, NetCdf4GroupsAndFill) {
    const fs::path file = fs::path(ORBIS_SHARED_DATA_DIR) / "netcdf/nc4uvt.nc";
    if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
    auto ambiguous = read(file, "T");
    ASSERT_FALSE(ambiguous.ok());
    EXPECT_NE(ambiguous.message().find("several groups"), std::string::npos) << ambiguous.message();
    auto f = read(file, "/grp1/T");
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ(f->nx(), 128u);
    EXPECT_EQ(f->ny(), 64u);
    EXPECT_EQ(f->nz(), 14u);
    // The file declares a -999 fill but its T has none; the values (labelled C) are near 266.
    EXPECT_EQ(f->validCount, f->values.size());
    EXPECT_GT(f->minValue, 150.0f);
    EXPECT_LT(f->maxValue, 350.0f);
    EXPECT_TRUE(f->times.empty()) << "\"Month\" has no reference date";
    EXPECT_EQ(f->timeSteps, 1u);
    auto json = describeVolumeJson(file.string());
    ASSERT_TRUE(json.ok()) << json.message();
    EXPECT_NE(json->find("\"fillValue\": -999"), std::string::npos);
}

}  // namespace orbis::layers
