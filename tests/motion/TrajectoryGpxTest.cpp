// GPX: the real files in ../shared/data/trajectory (a track, a route with waypoints), segments
// and routes written here, and broken files that must give a clear error naming the line.
#include "formats/motion/TrajectoryFile.h"
#include "formats/motion/TrajectoryGpx.h"
#include "MotionTestUtil.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace orbis::motion {
namespace {

using namespace test;

#define SKIP_WITHOUT(path)                                                                     \
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << (path) << " (../shared/data is optional)"

std::string gpxError(const std::string& text) {
    auto r = parseGpx(text, "t.gpx");
    EXPECT_FALSE(r.ok());
    return r.ok() ? std::string() : r.message();
}

void expectInside(const std::vector<GpxPoint>& points, const GpxBounds& b) {
    for (const GpxPoint& p : points) {
        EXPECT_GE(p.latDeg, b.minLatDeg) << "line " << p.line;
        EXPECT_LE(p.latDeg, b.maxLatDeg) << "line " << p.line;
        EXPECT_GE(p.lonDeg, b.minLonDeg) << "line " << p.line;
        EXPECT_LE(p.lonDeg, b.maxLonDeg) << "line " << p.line;
    }
}

// ------------------------------------------------------------------------- real files

TEST(GpxRealFiles, TestTrk2HasAnUntimedTrackAndATimedOne) {
    const auto path = sharedData("trajectory/test_trk2.gpx");
    SKIP_WITHOUT(path);
    auto gpx = readGpx(path.string());
    ASSERT_TRUE(gpx.ok()) << gpx.message();
    EXPECT_EQ(gpx->version, "1.1");
    ASSERT_EQ(gpx->tracks.size(), 2u);
    EXPECT_EQ(gpx->tracks[0].name, "15-NOV-08TWEE #2");
    EXPECT_EQ(gpx->tracks[0].points.size(), 19u);
    EXPECT_FALSE(gpx->tracks[0].points[0].time.has_value());
    EXPECT_EQ(gpx->tracks[1].name, "ACTIVE LOG");
    EXPECT_EQ(gpx->tracks[1].points.size(), 8u);
    EXPECT_EQ(gpx->tracks[1].segments, 1u);
    ASSERT_TRUE(gpx->bounds.has_value());
    EXPECT_EQ(gpx->bounds->minLatDeg, -46.055888962);
    for (const GpxTrack& t : gpx->tracks) expectInside(t.points, *gpx->bounds);
    EXPECT_NEAR(*gpx->tracks[0].points[0].ele, 34.744873, 1e-9);
}

TEST(GpxRealFiles, TestTrk2BecomesATrajectoryOfItsTimedTrack) {
    const auto path = sharedData("trajectory/test_trk2.gpx");
    SKIP_WITHOUT(path);
    auto tr = readTrajectory(path.string());   // the first track has no times: the second is taken
    ASSERT_TRUE(tr.ok()) << tr.message();
    EXPECT_EQ(tr->sampleCount(), 8u);
    EXPECT_EQ(tr->timeRange().begin, *parseIso8601("2009-04-27T02:36:23Z"));
    EXPECT_EQ(tr->timeRange().end, *parseIso8601("2009-04-27T02:39:00Z"));
    const TrajectoryBounds& b = tr->bounds();
    // The samples' own coordinates back through ECEF: ~1e-12 degrees.
    EXPECT_NEAR(b.southDeg, -46.036184700, 1e-9);
    EXPECT_NEAR(b.northDeg, -46.035645744, 1e-9);
    EXPECT_NEAR(b.westDeg, 170.171738164, 1e-9);
    EXPECT_NEAR(b.eastDeg, 170.172108812, 1e-9);
    EXPECT_NEAR(b.minHeight, 8.789185, 1e-6);   // <ele> above MSL, no geoid given: as ellipsoid heights
    EXPECT_NEAR(b.maxHeight, 14.076416, 1e-6);
    EXPECT_EQ(tr->warnings().size(), 1u);       // ... which is said
    EXPECT_EQ(tr->derivedAttitudes(), 8u);
    // The boat heads north-west from the first point to the fourth (heading from the motion).
    const auto p = tr->pose(*parseIso8601("2009-04-27T02:37:45Z"));
    EXPECT_GT(p->headingDeg, 270.0);
    EXPECT_LT(p->headingDeg, 360.0);
    // By name and by position, the untimed track is refused with the line of its first point.
    TrajectoryFileOptions o;
    o.gpxTrack = "1";
    auto first = readTrajectory(path.string(), o);
    ASSERT_FALSE(first.ok());
    EXPECT_TRUE(contains(first.message(), "test_trk2.gpx: line 16: a point without <time>")) << first.message();
    o.gpxTrack = "ACTIVE LOG";
    EXPECT_TRUE(readTrajectory(path.string(), o).ok());
    o.gpxTrack = "nope";
    auto none = readTrajectory(path.string(), o);
    EXPECT_TRUE(contains(none.message(), "no track or route 'nope' (there are: track 1 '15-NOV-08TWEE #2', track 2 'ACTIVE LOG')"))
        << none.message();
}

TEST(GpxRealFiles, FellsLoopRouteAndWaypoints) {
    const auto path = sharedData("trajectory/fells_loop.gpx");
    SKIP_WITHOUT(path);
    auto gpx = readGpx(path.string());
    ASSERT_TRUE(gpx.ok()) << gpx.message();
    EXPECT_EQ(gpx->version, "1.0");
    ASSERT_EQ(gpx->tracks.size(), 1u);
    const GpxTrack& route = gpx->tracks[0];
    EXPECT_TRUE(route.route);
    EXPECT_EQ(route.name, "BELLEVUE");
    EXPECT_EQ(route.points.size(), 46u);
    EXPECT_EQ(gpx->waypoints.size(), 86u);
    ASSERT_TRUE(gpx->bounds.has_value());
    expectInside(route.points, *gpx->bounds);
    expectInside(gpx->waypoints, *gpx->bounds);
    auto [tmin, tmax] = std::minmax_element(route.points.begin(), route.points.end(),
                                            [](const GpxPoint& a, const GpxPoint& b) { return *a.time < *b.time; });
    EXPECT_EQ(*tmin->time, *parseIso8601("2001-06-02T00:18:14Z"));
    EXPECT_EQ(*tmax->time, *parseIso8601("2001-11-28T21:05:28Z"));
    auto [south, north] = std::minmax_element(route.points.begin(), route.points.end(),
                                              [](const GpxPoint& a, const GpxPoint& b) { return a.latDeg < b.latDeg; });
    EXPECT_EQ(south->latDeg, 42.43095);
    EXPECT_EQ(north->latDeg, 42.46711);
    EXPECT_EQ(route.points[0].line, 703u);
}

TEST(GpxRealFiles, FellsLoopRouteTimesAreNotATrajectory) {
    // The route's times are when each waypoint was made, not a journey: repeated, then going back.
    const auto path = sharedData("trajectory/fells_loop.gpx");
    SKIP_WITHOUT(path);
    auto tr = readTrajectory(path.string());
    ASSERT_FALSE(tr.ok());
    EXPECT_TRUE(contains(tr.message(), "fells_loop.gpx: line 720: time 2001-11-07T23:53:41.000Z is the same as line 712's"))
        << tr.message();
    TrajectoryFileOptions o;
    o.trajectory.duplicateTimes = DuplicateTimes::KeepFirst;
    auto kept = readTrajectory(path.string(), o);
    ASSERT_FALSE(kept.ok());
    EXPECT_TRUE(contains(kept.message(), "fells_loop.gpx: line 736: time 2001-06-02T03:26:55.000Z is before line 728's")) << kept.message();
}

// ------------------------------------------------------------------------- written here

const char* kTwoSegments = R"(<?xml version="1.0" encoding="UTF-8"?>
<!-- a comment -->
<gpx:gpx version="1.1" creator="test &amp; co" xmlns:gpx="http://www.topografix.com/GPX/1/1">
  <gpx:trk><gpx:name>Walk &lt;1&gt;</gpx:name>
    <gpx:trkseg>
      <gpx:trkpt lat="46.000" lon="7.000"><gpx:ele>500</gpx:ele><gpx:time>2024-05-01T12:00:00Z</gpx:time></gpx:trkpt>
      <gpx:trkpt lat='46.001' lon='7.000'><gpx:ele>510</gpx:ele><gpx:time>2024-05-01T12:01:00Z</gpx:time>
        <gpx:extensions><x:speed xmlns:x="urn:x">1.8</x:speed><x:time xmlns:x="urn:x">bogus</x:time></gpx:extensions></gpx:trkpt>
    </gpx:trkseg>
    <gpx:trkseg>
      <gpx:trkpt lat="46.002" lon="7.000"><gpx:time>2024-05-01T12:02:00Z</gpx:time></gpx:trkpt>
    </gpx:trkseg>
  </gpx:trk>
</gpx:gpx>
)";

TEST(GpxWritten, SegmentsAreConcatenatedAndNamespacesIgnored) {
    auto gpx = parseGpx(kTwoSegments, "t.gpx");
    ASSERT_TRUE(gpx.ok()) << gpx.message();
    ASSERT_EQ(gpx->tracks.size(), 1u);
    EXPECT_EQ(gpx->tracks[0].name, "Walk <1>");
    EXPECT_EQ(gpx->tracks[0].segments, 2u);
    ASSERT_EQ(gpx->tracks[0].points.size(), 3u);
    EXPECT_EQ(gpx->tracks[0].points[2].line, 11u);
    auto samples = gpxTrajectorySamples(*gpx, "t.gpx");
    ASSERT_TRUE(samples.ok()) << samples.message();
    const auto& s = *samples;
    EXPECT_EQ(s[0].altRef, AltitudeRef::MeanSeaLevel);
    EXPECT_EQ(s[0].alt, 500.0);
    EXPECT_EQ(s[2].altRef, AltitudeRef::Ground);   // no <ele>: on the ground
    EXPECT_EQ(s[2].alt, 0.0);
    EXPECT_EQ(s[1].t - s[0].t, 60 * kNsPerSecond);
    EXPECT_FALSE(s[0].headingDeg.has_value());
    // Northward: heading 0 from the motion, wings level.
    auto tr = Trajectory::create(*samples, {}, "t.gpx");
    ASSERT_TRUE(tr.ok()) << tr.message();
    const auto p = tr->pose(s[0].t + 30 * kNsPerSecond);
    EXPECT_NEAR(headingDiff(p->headingDeg, 0.0), 0.0, 1e-3);
    EXPECT_NEAR(p->rollDeg, 0.0, 1e-9);
}

TEST(GpxWritten, RouteWithTimesIsATrajectory) {
    auto gpx = parseGpx(R"(<gpx version="1.0"><wpt lat="1" lon="2"/><rte><name>R</name>
        <rtept lat="46" lon="7"><time>2024-05-01T12:00:00Z</time></rtept>
        <rtept lat="46" lon="7.01"><time>2024-05-01T12:10:00Z</time></rtept></rte></gpx>)",
                        "t.gpx");
    ASSERT_TRUE(gpx.ok()) << gpx.message();
    EXPECT_EQ(gpx->waypoints.size(), 1u);
    auto samples = gpxTrajectorySamples(*gpx, "t.gpx", "R");
    ASSERT_TRUE(samples.ok()) << samples.message();
    EXPECT_EQ(samples->size(), 2u);
    EXPECT_EQ((*samples)[1].line, 3u);
}

TEST(GpxWritten, FileWithoutTracks) {
    auto gpx = parseGpx(R"(<gpx version="1.1"><wpt lat="1" lon="2"><time>2024-05-01T12:00:00Z</time></wpt></gpx>)", "t.gpx");
    ASSERT_TRUE(gpx.ok()) << gpx.message();
    auto s = gpxTrajectorySamples(*gpx, "t.gpx");
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.message(), "t.gpx: no track or route in the file (1 waypoints")) << s.message();
}

TEST(GpxWritten, NoTrackWithTimesSaysWhy) {
    auto gpx = parseGpx(R"(<gpx><trk><name>A</name><trkseg><trkpt lat="1" lon="2"/></trkseg></trk></gpx>)", "t.gpx");
    ASSERT_TRUE(gpx.ok()) << gpx.message();
    auto s = gpxTrajectorySamples(*gpx, "t.gpx");
    EXPECT_EQ(s.message(), "t.gpx: no track or route has a time at every point (track 1 'A': 1 points, 0 with a time)");
}

// ------------------------------------------------------------------------- broken

TEST(GpxBroken, MismatchedTagNamesTheLines) {
    EXPECT_EQ(gpxError("<gpx>\n<trk>\n<trkseg>\n</trk>\n</gpx>\n"), "t.gpx: line 4: XML: </trk> closes <trkseg> (opened at line 3)");
}

TEST(GpxBroken, TruncatedFile) {
    EXPECT_EQ(gpxError("<gpx>\n<trk>\n<trkseg>\n<trkpt lat=\"1\" lon=\"2\">"), "t.gpx: XML: the file ends inside <trkpt> (opened at line 4)");
    EXPECT_TRUE(contains(gpxError("<gpx>\n<trk><trkseg><trkpt lat=\"1\" lo"), "line 2: XML: the file ends inside the tag <trkpt>"));
}

TEST(GpxBroken, NotGpx) {
    EXPECT_EQ(gpxError("<?xml version=\"1.0\"?>\n<kml><Document/></kml>"), "t.gpx: line 2: not a GPX file: the root element is <kml>, not <gpx>");
    EXPECT_TRUE(contains(gpxError("time,lat,lon\n1,2,3\n"), "t.gpx: line 1: XML: text before the root element"));
    EXPECT_TRUE(contains(gpxError(""), "t.gpx: not a GPX file: no XML element in it"));
}

TEST(GpxBroken, BadPointValuesNameTheLine) {
    EXPECT_EQ(gpxError("<gpx>\n<wpt lon=\"2\"/></gpx>"), "t.gpx: line 2: <wpt> without a lat attribute");
    EXPECT_EQ(gpxError("<gpx><rte>\n<rtept lat=\"north\" lon=\"2\"/></rte></gpx>"), "t.gpx: line 2: <rtept> lat 'north' is not a number");
    EXPECT_EQ(gpxError("<gpx><wpt lat=\"1\" lon=\"200\"/></gpx>"), "t.gpx: line 1: <wpt> lon 200 is outside -180..180");
    EXPECT_EQ(gpxError("<gpx><wpt lat=\"1\" lon=\"2\">\n<ele>high</ele></wpt></gpx>"), "t.gpx: line 2: <ele> 'high' is not a number");
    const std::string t = gpxError("<gpx><wpt lat=\"1\" lon=\"2\">\n\n<time>noon</time></wpt></gpx>");
    EXPECT_TRUE(contains(t, "t.gpx: line 3: <time>: ")) << t;
}

TEST(GpxBroken, MalformedXml) {
    EXPECT_TRUE(contains(gpxError("<gpx><wpt lat=1 lon=\"2\"/></gpx>"), "attribute lat without quotes"));
    EXPECT_TRUE(contains(gpxError("<gpx>&bogus;</gpx>"), "unknown entity '&bogus;'"));
    EXPECT_TRUE(contains(gpxError("<gpx><!-- open"), "unterminated comment"));
    EXPECT_TRUE(contains(gpxError("<gpx></gpx><gpx></gpx>"), "a second root element <gpx>"));
    EXPECT_TRUE(contains(gpxError("<gpx></gpx>\ntrailing"), "line 2: XML: text after the root element"));
    EXPECT_TRUE(contains(gpxError("</gpx>"), "end tag </gpx> without a start tag"));
    EXPECT_TRUE(contains(gpxError("<gpx>< trk></gpx>"), "'<' not followed by a tag name"));
}

// Found by mutating real files (../shared/data/bad/README.md): a track's elements inside a
// waypoint used to be taken for a track that did not exist (a null dereference). They are
// someone's extension there, not a track.
TEST(GpxBroken, TrackElementsInsideAWaypointAreNotATrack) {
    for (const char* inner : {"<trkpt lat=\"1\" lon=\"2\"><time>2001-01-01T00:00:00Z</time></trkpt>", "<trk><trkseg></trkseg></trk>",
                              "<rte><name>x</name><rtept lat=\"1\" lon=\"2\"/></rte>", "<trkseg><trkpt lat=\"3\" lon=\"4\"/></trkseg>"}) {
        const std::string text = std::string("<gpx version=\"1.1\">\n<wpt lat=\"1\" lon=\"2\">\n") + inner + "\n</wpt>\n</gpx>\n";
        auto gpx = parseGpx(text, "t.gpx");
        ASSERT_TRUE(gpx.ok()) << inner << ": " << gpx.message();
        EXPECT_TRUE(gpx->tracks.empty()) << inner;
        ASSERT_EQ(gpx->waypoints.size(), 1u) << inner;
        EXPECT_EQ(gpx->waypoints[0].latDeg, 1.0) << inner;
        auto s = gpxTrajectorySamples(*gpx, "t.gpx");
        EXPECT_TRUE(contains(s.message(), "t.gpx: no track or route in the file (1 waypoints")) << s.message();
    }
    // A track's point with a waypoint's children inside keeps only its own.
    auto gpx = parseGpx("<gpx><trk><trkseg><trkpt lat=\"1\" lon=\"2\"><wpt lat=\"5\" lon=\"6\"><ele>9</ele></wpt>"
                        "<ele>3</ele></trkpt></trkseg></trk></gpx>",
                        "t.gpx");
    ASSERT_TRUE(gpx.ok()) << gpx.message();
    ASSERT_EQ(gpx->tracks.size(), 1u);
    ASSERT_EQ(gpx->tracks[0].points.size(), 1u);
    EXPECT_EQ(gpx->tracks[0].points[0].ele, 3.0);
    EXPECT_TRUE(gpx->waypoints.empty());
}

TEST(GpxBroken, TheFilesThatCrashedSayWhy) {
    for (const char* name : {"bad/gpx-trkpt-in-wpt.gpx", "bad/gpx-trkseg-in-wpt.gpx", "bad/gpx-name-in-rte-in-wpt.gpx"}) {
        const auto path = sharedData(name);
        SKIP_WITHOUT(path);
        auto tr = readTrajectory(path.string());
        ASSERT_FALSE(tr.ok()) << name;
        EXPECT_TRUE(contains(tr.message(), path.filename().string() + ": no track or route in the file")) << tr.message();
    }
}

TEST(GpxBroken, FileMissingOrTooBig) {
    auto missing = readGpx((tempDir() / "none.gpx").string());
    EXPECT_TRUE(contains(missing.message(), "none.gpx: cannot read")) << missing.message();
    const std::string path = (tempDir() / "huge.gpx").string();
    std::ofstream(path) << "<gpx>";
    std::filesystem::resize_file(path, kMaxGpxBytes + 1);   // sparse: no disk used
    auto big = readGpx(path);
    EXPECT_TRUE(contains(big.message(), "MiB a GPX file may have")) << big.message();
    std::filesystem::remove(path);
}

TEST(GpxBroken, BrokenFileThroughReadTrajectory) {
    const std::string path = writeText("broken.gpx", "<?xml version=\"1.0\"?>\n<gpx>\n<trk>\n<trkseg>\n</gpx>\n");
    auto tr = readTrajectory(path);
    ASSERT_FALSE(tr.ok());
    EXPECT_TRUE(contains(tr.message(), "broken.gpx: line 5: XML: </gpx> closes <trkseg> (opened at line 4)")) << tr.message();
    // Without the .gpx extension, the content says it is XML.
    const std::string noExt = writeText("broken-gpx", "\n  <gpx>\n<trk>\n<trkseg>\n</gpx>\n");
    auto sniffed = readTrajectory(noExt);
    EXPECT_TRUE(contains(sniffed.message(), "XML: </gpx> closes <trkseg>")) << sniffed.message();
}

}  // namespace
}  // namespace orbis::motion
