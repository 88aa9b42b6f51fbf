// Trajectory CSV: column names and units, time forms, altitude references, separators, and
// every error a file can give (each naming the file, line and column).
#include "formats/motion/TrajectoryCsv.h"
#include "formats/motion/TrajectoryFile.h"
#include "MotionTestUtil.h"

#include <gtest/gtest.h>

#include <numbers>

namespace orbis::motion {
namespace {

using namespace test;

TrajectoryCsv parse(const std::string& text, const CsvOptions& o = {}) {
    auto r = parseTrajectoryCsv(text, "t.csv", o);
    EXPECT_TRUE(r.ok()) << r.message();
    return r.ok() ? std::move(*r) : TrajectoryCsv{};
}

std::string parseError(const std::string& text) {
    auto r = parseTrajectoryCsv(text, "t.csv");
    EXPECT_FALSE(r.ok());
    return r.ok() ? std::string() : r.message();
}

TEST(TrajectoryCsvRead, IsoTimesAndDegrees) {
    const TrajectoryCsv csv = parse(
        "# a flight\n"
        "time,lon,lat,alt_hae,yaw,pitch,roll\n"
        "2024-05-01T12:00:00Z,7.5,46.25,1200,90,5,-10\n"
        "\n"
        "2024-05-01T12:00:01.25Z,7.501,46.25,1210,91,,NaN\n");
    ASSERT_EQ(csv.samples.size(), 2u);
    EXPECT_EQ(csv.timeUnit, "iso8601");
    EXPECT_EQ(*csv.altitudeRef, AltitudeRef::Ellipsoid);
    const TrajectorySample& a = csv.samples[0];
    EXPECT_EQ(a.t, *parseIso8601("2024-05-01T12:00:00Z"));
    EXPECT_EQ(a.lonDeg, 7.5);
    EXPECT_EQ(a.latDeg, 46.25);
    EXPECT_EQ(a.alt, 1200.0);
    EXPECT_EQ(a.altRef, AltitudeRef::Ellipsoid);
    EXPECT_EQ(*a.headingDeg, 90.0);
    EXPECT_EQ(*a.pitchDeg, 5.0);
    EXPECT_EQ(*a.rollDeg, -10.0);
    EXPECT_EQ(a.line, 3u);
    const TrajectorySample& b = csv.samples[1];
    EXPECT_EQ(b.t - a.t, 1'250'000'000);
    EXPECT_FALSE(b.pitchDeg.has_value());   // empty: absent
    EXPECT_FALSE(b.rollDeg.has_value());    // NaN: absent
    EXPECT_EQ(b.line, 5u);
}

TEST(TrajectoryCsvRead, RadiansFromTheColumnNames) {
    const TrajectoryCsv csv = parse("t_s,lon_rad,lat (rad),alt,yaw_rad,Pitch [rad],roll_deg\n"
                                    "10,0.5,-0.25,0,3.14159265358979,0.1,30\n");
    const TrajectorySample& s = csv.samples[0];
    const double toDeg = 180.0 / std::numbers::pi;
    EXPECT_DOUBLE_EQ(s.lonDeg, 0.5 * toDeg);
    EXPECT_DOUBLE_EQ(s.latDeg, -0.25 * toDeg);
    EXPECT_DOUBLE_EQ(*s.headingDeg, 3.14159265358979 * toDeg);
    EXPECT_DOUBLE_EQ(*s.pitchDeg, 0.1 * toDeg);
    EXPECT_EQ(*s.rollDeg, 30.0);
    EXPECT_EQ(s.t, 10 * kNsPerSecond);
    EXPECT_EQ(csv.timeUnit, "s");
}

TEST(TrajectoryCsvRead, NumericTimesAreExactToTheNanosecond) {
    const TrajectoryCsv s = parse("time,lat,lon\n1700000000.123456789,1,2\n");
    EXPECT_EQ(s.samples[0].t, 1'700'000'000'123'456'789);   // a double would lose the last digits
    const TrajectoryCsv ms = parse("Time (ms),lat,lon\n1700000000123.5,1,2\n");
    EXPECT_EQ(ms.samples[0].t, 1'700'000'000'123'500'000);
    EXPECT_EQ(ms.timeUnit, "ms");
    const TrajectoryCsv us = parse("timestamp_us,lat,lon\n-1500,1,2\n");
    EXPECT_EQ(us.samples[0].t, -1'500'000);
    const TrajectoryCsv exp = parse("t,lat,lon\n1.5e3,1,2\n");
    EXPECT_EQ(exp.samples[0].t, 1500 * kNsPerSecond);
}

TEST(TrajectoryCsvRead, UnitlessTimeUnitFromTheFirstNumber) {
    EXPECT_EQ(parse("time,lat,lon\n1700000000000,1,2\n").timeUnit, "ms");
    EXPECT_EQ(parse("time,lat,lon\n1700000000000000,1,2\n").timeUnit, "us");
    EXPECT_EQ(parse("time,lat,lon\n1700000000000000000,1,2\n").timeUnit, "ns");
    const TrajectoryCsv rel = parse("time,lat,lon\n0.5,1,2\n", {.timeOffset = 100 * kNsPerSecond});
    EXPECT_EQ(rel.timeUnit, "s");
    EXPECT_EQ(rel.samples[0].t, 100'500'000'000);
}

TEST(TrajectoryCsvRead, AltitudeReferenceFromTheName) {
    EXPECT_EQ(*parse("time,lat,lon,alt_msl\n0,1,2,3\n").altitudeRef, AltitudeRef::MeanSeaLevel);
    EXPECT_EQ(*parse("time,lat,lon,height\n0,1,2,3\n").altitudeRef, AltitudeRef::Ellipsoid);
    EXPECT_EQ(*parse("time,lat,lon,HAE (m)\n0,1,2,3\n").altitudeRef, AltitudeRef::Ellipsoid);
    EXPECT_EQ(*parse("time,lat,lon,alt_agl\n0,1,2,3\n").altitudeRef, AltitudeRef::Ground);
    EXPECT_EQ(*parse("time,lat,lon,Height above ground\n0,1,2,3\n").altitudeRef, AltitudeRef::Ground);
    // Unspecified: the option (mean sea level by default).
    EXPECT_EQ(*parse("time,lat,lon,alt\n0,1,2,3\n").altitudeRef, AltitudeRef::MeanSeaLevel);
    const TrajectoryCsv e = parse("time,lat,lon,altitude\n0,1,2,3\n", {.altitudeRef = AltitudeRef::Ellipsoid});
    EXPECT_EQ(e.samples[0].altRef, AltitudeRef::Ellipsoid);
    // Feet.
    EXPECT_NEAR(parse("time,lat,lon,alt_ft\n0,1,2,1000\n").samples[0].alt, 304.8, 1e-9);
}

TEST(TrajectoryCsvRead, NoAltitudeColumnMeansOnTheGround) {
    const TrajectoryCsv csv = parse("time,lat,lon\n0,1,2\n");
    EXPECT_FALSE(csv.altitudeRef.has_value());
    EXPECT_EQ(csv.samples[0].altRef, AltitudeRef::Ground);
    EXPECT_EQ(csv.samples[0].alt, 0.0);
}

TEST(TrajectoryCsvRead, SeveralAltitudesTheEllipsoidHeightWins) {
    const TrajectoryCsv csv = parse("time,lat,lon,alt,agl,hae\n0,1,2,100,50,148\n");
    EXPECT_EQ(*csv.altitudeRef, AltitudeRef::Ellipsoid);
    EXPECT_EQ(csv.samples[0].alt, 148.0);
    EXPECT_EQ(csv.ignored, (std::vector<std::string>{"alt", "agl"}));
}

TEST(TrajectoryCsvRead, SemicolonsTabsDecimalCommasQuotesAndCrlf) {
    const TrajectoryCsv semi = parse("\xEF\xBB\xBFtime;lat;lon;alt\r\n0;46,5;7,25;\"1200,5\"\r\n");
    EXPECT_EQ(semi.samples[0].latDeg, 46.5);
    EXPECT_EQ(semi.samples[0].lonDeg, 7.25);
    EXPECT_EQ(semi.samples[0].alt, 1200.5);
    const TrajectoryCsv tab = parse("time\tlatitude\tlongitude\theading\n0\t46.5\t7.25\t12\n");
    EXPECT_EQ(*tab.samples[0].headingDeg, 12.0);
    const TrajectoryCsv names = parse("\"Time (UTC)\",Latitude,Longitude,\"Platform Heading Angle\",extra\n"
                                      "2024-05-01 12:00:00,46.5,7.25,12,x\n");
    EXPECT_EQ(*names.samples[0].headingDeg, 12.0);
    EXPECT_EQ(names.ignored, std::vector<std::string>{"extra"});
}

TEST(TrajectoryCsvRead, ShortRowsLeaveTheAnglesAbsent) {
    const TrajectoryCsv csv = parse("time,lat,lon,alt,heading,pitch,roll\n0,1,2,3\n");
    EXPECT_FALSE(csv.samples[0].headingDeg.has_value());
}

// ------------------------------------------------------------------------- errors

TEST(TrajectoryCsvErrors, MissingColumnsListTheNamesAccepted) {
    const std::string e = parseError("time,x,y,alt\n0,1,2,3\n");
    EXPECT_TRUE(contains(e, "t.csv: line 1: no column for latitude (lat, latitude")) << e;
    EXPECT_TRUE(contains(e, "longitude (lon, long, lng, longitude")) << e;
    EXPECT_FALSE(contains(e, "time (")) << e;
    EXPECT_TRUE(contains(parseError("lat,lon\n1,2\n"), "no column for time (time, timestamp, t, utc")) << parseError("lat,lon\n1,2\n");
}

TEST(TrajectoryCsvErrors, NotANumberNamesLineAndColumn) {
    EXPECT_EQ(parseError("time,lon,lat\n0,1,2\n1,2,abc\n"), "t.csv: line 3, column 3 (lat): 'abc' is not a number");
    EXPECT_EQ(parseError("time,lon,lat,yaw\n0,1,2,east\n"), "t.csv: line 2, column 4 (yaw): 'east' is not a number");
    const std::string t = parseError("time,lon,lat\nyesterday,1,2\n");
    EXPECT_TRUE(contains(t, "t.csv: line 2, column 1 (time): 'yesterday' is neither a number nor an ISO 8601 time")) << t;
}

TEST(TrajectoryCsvErrors, NaNPositionOrTimeNamesTheLine) {
    EXPECT_TRUE(contains(parseError("time,lon,lat\n0,1,2\n1,NaN,2\n"), "t.csv: line 3, column 2 (lon): no longitude ('NaN')"));
    EXPECT_TRUE(contains(parseError("time,lon,lat,alt\n0,1,2,\n"), "t.csv: line 2, column 4 (alt): no altitude"));
    EXPECT_TRUE(contains(parseError("time,lon,lat\n,1,2\n"), "t.csv: line 2, column 1 (time): no time"));
}

TEST(TrajectoryCsvErrors, TooManyCells) {
    EXPECT_EQ(parseError("time,lon,lat\n0,1,2\n1,2,3,4\n"), "t.csv: line 3: 4 cells, the header (line 1) has 3");
}

TEST(TrajectoryCsvErrors, EmptyFileOrNoRows) {
    EXPECT_TRUE(contains(parseError(""), "t.csv: no header line"));
    EXPECT_TRUE(contains(parseError("# only\n\n# comments\n"), "t.csv: no header line"));
    EXPECT_EQ(parseError("# c\ntime,lat,lon\n\n"), "t.csv: no data rows after the header (line 2)");
}

TEST(TrajectoryCsvErrors, TwoColumnsForOneValue) {
    EXPECT_EQ(parseError("time,lat,latitude,lon\n0,1,1,2\n"), "t.csv: line 1: columns 2 (lat) and 3 (latitude) give the same value");
}

TEST(TrajectoryCsvErrors, TimeOutsideInt64Nanoseconds) {
    EXPECT_TRUE(contains(parseError("time_s,lat,lon\n99999999999,1,2\n"), "past what int64 nanoseconds"));
}

TEST(TrajectoryCsvErrors, MissingFile) {
    auto r = readTrajectoryCsv((tempDir() / "no-such.csv").string());
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.message(), "no-such.csv: cannot read")) << r.message();
}

TEST(TrajectoryCsvErrors, FileOverTheLimitIsRefusedUnread) {
    // A sparse file: its size says 256 MiB + 1, it takes no disk.
    const std::string path = (tempDir() / "huge.csv").string();
    std::ofstream(path) << "time,lat,lon\n";
    std::filesystem::resize_file(path, kMaxTrajectoryCsvBytes + 1);
    auto r = readTrajectoryCsv(path);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.message(), "is more than the 256 MiB a trajectory CSV may have")) << r.message();
    std::filesystem::remove(path);
}

// ------------------------------------------------------------------------- whole files

TEST(TrajectoryCsvFile, UnsortedTimesNameTheLines) {
    const std::string path = writeText("unsorted.csv", "time,lat,lon,alt\n0,46,7,0\n10,46.001,7,0\n# pause\n5,46.002,7,0\n");
    auto r = readTrajectory(path);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.message(), "unsorted.csv: line 5: time 1970-01-01T00:00:05.000Z is before line 3's")) << r.message();
}

TEST(TrajectoryCsvFile, DuplicateTimesAreAnErrorOrKeepFirst) {
    const std::string path = writeText("dup.csv", "time,lat,lon,alt\n0,46,7,0\n10,46.001,7,0\n10,46.002,7,0\n20,46.003,7,0\n");
    auto r = readTrajectory(path);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.message(), "dup.csv: line 4: time 1970-01-01T00:00:10.000Z is the same as line 3's")) << r.message();
    TrajectoryFileOptions o;
    o.trajectory.duplicateTimes = DuplicateTimes::KeepFirst;
    auto kept = readTrajectory(path, o);
    ASSERT_TRUE(kept.ok()) << kept.message();
    EXPECT_EQ(kept->sampleCount(), 3u);
}

TEST(TrajectoryCsvFile, ReadsAFlightEndToEnd) {
    const std::string path = writeText("flight.csv",
                                       "time,lon,lat,alt_hae,heading_deg,pitch_deg,roll_deg\n"
                                       "2024-05-01T12:00:00Z,7.0,46.0,1000,90,0,0\n"
                                       "2024-05-01T12:00:10Z,7.01,46.0,1000,90,0,10\n"
                                       "2024-05-01T12:00:20Z,7.02,46.0,1000,90,0,20\n");
    auto tr = readTrajectory(path);
    ASSERT_TRUE(tr.ok()) << tr.message();
    EXPECT_EQ(tr->sampleCount(), 3u);
    EXPECT_EQ(tr->name(), path);
    const auto p = tr->pose(*parseIso8601("2024-05-01T12:00:05Z"));
    EXPECT_NEAR(p->headingDeg, 90.0, 1e-3);
    EXPECT_NEAR(p->rollDeg, 5.0, 1e-3);
    EXPECT_NEAR(p->height, 1000.0, 0.01);
    EXPECT_TRUE(tr->warnings().empty());
}

}  // namespace
}  // namespace orbis::motion
