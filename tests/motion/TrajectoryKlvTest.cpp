// Platform poses from MISB ST 0601: packets built here (through the FMV encoder and decoder),
// a raw .bin stream, an FMV pose CSV, and the real reference packet.
#include "formats/fmv/St0601.h"
#include "formats/fmv/St0601Encode.h"
#include "formats/motion/TrajectoryFile.h"
#include "formats/motion/TrajectoryKlv.h"
#include "MotionTestUtil.h"

#include <gtest/gtest.h>

namespace orbis::motion {
namespace {

using namespace test;
using fmv::St0601Packet;

constexpr uint64_t kUs0 = 1'700'000'000'000'000ull;   // µs since 1970

St0601Packet packet(uint64_t timeUs, double lat, double lon) {
    St0601Packet p;
    p.precisionTimeUs = timeUs;
    p.sensorLatitudeDeg = lat;
    p.sensorLongitudeDeg = lon;
    p.sensorEllipsoidHeight = 1500.0;
    p.platformHeadingDeg = 45.0;
    p.platformPitchFullDeg = 3.0;
    p.platformRollFullDeg = -8.0;
    return p;
}

/// Through the encoder and back: what a stream would give (values within one step of the
/// tags' integer mappings).
St0601Packet roundTrip(const St0601Packet& p) {
    auto r = fmv::decodeSt0601(fmv::encodeSt0601(p));
    EXPECT_TRUE(r.ok()) << r.message();
    return *r;
}

TEST(TrajectoryKlv, PacketsGiveThePlatformPose) {
    std::vector<St0601Packet> packets;
    for (int i = 0; i < 5; ++i) packets.push_back(roundTrip(packet(kUs0 + uint64_t(i) * 100'000, 46.0 + 1e-4 * i, 7.0 + 1e-4 * i)));
    const KlvSamples s = samplesFromSt0601(packets);
    ASSERT_EQ(s.samples.size(), 5u);
    const TrajectorySample& a = s.samples[2];
    EXPECT_EQ(a.t, TimeNs(kUs0 + 200'000) * 1000);
    // ST 0601 tags 13/14: int32 over ±90/±180, a step of 4.2e-8 / 8.4e-8 degrees.
    EXPECT_NEAR(a.latDeg, 46.0002, 1e-7);
    EXPECT_NEAR(a.lonDeg, 7.0002, 1e-7);
    EXPECT_EQ(a.altRef, AltitudeRef::Ellipsoid);
    EXPECT_NEAR(a.alt, 1500.0, 0.5);           // tag 75: uint16 over 19 900 m, 0.3 m steps
    EXPECT_NEAR(*a.headingDeg, 45.0, 0.01);    // tag 5: uint16 over 360 degrees
    EXPECT_NEAR(*a.pitchDeg, 3.0, 1e-6);       // tag 90: int32 over ±90 degrees
    EXPECT_NEAR(*a.rollDeg, -8.0, 1e-6);
    // The trajectory shows the platform's attitude in the ST 0601 convention.
    auto tr = Trajectory::create(s.samples, {}, "packets");
    ASSERT_TRUE(tr.ok()) << tr.message();
    const auto p = tr->pose(TimeNs(kUs0 + 250'000) * 1000);
    EXPECT_NEAR(p->headingDeg, 45.0, 0.01);
    EXPECT_NEAR(p->pitchDeg, 3.0, 1e-3);
    EXPECT_NEAR(p->rollDeg, -8.0, 1e-3);
}

TEST(TrajectoryKlv, TrueAltitudeIsAboveMeanSeaLevel) {
    St0601Packet p = packet(kUs0, 46.0, 7.0);
    p.sensorEllipsoidHeight.reset();
    p.sensorTrueAltitude = 1200.0;
    p.platformHeadingDeg.reset();
    p.platformPitchFullDeg.reset();
    p.platformPitchDeg = 2.0;   // tag 6, the short-range pitch, when 90 is absent
    const KlvSamples s = samplesFromSt0601({p});
    ASSERT_EQ(s.samples.size(), 1u);
    EXPECT_EQ(s.samples[0].altRef, AltitudeRef::MeanSeaLevel);
    EXPECT_EQ(s.samples[0].alt, 1200.0);
    EXPECT_FALSE(s.samples[0].headingDeg.has_value());   // left for the motion
    EXPECT_EQ(*s.samples[0].pitchDeg, 2.0);
}

TEST(TrajectoryKlv, UnusablePacketsAreLeftOutAndCounted) {
    std::vector<St0601Packet> packets;
    packets.push_back(packet(kUs0, 46.0, 7.0));
    St0601Packet noTime = packet(kUs0 + 1, 46.0, 7.0);
    noTime.precisionTimeUs.reset();
    packets.push_back(noTime);
    St0601Packet noHeight = packet(kUs0 + 2, 46.0, 7.0);
    noHeight.sensorEllipsoidHeight.reset();
    packets.push_back(noHeight);
    St0601Packet noLat = packet(kUs0 + 3, 46.0, 7.0);
    noLat.sensorLatitudeDeg.reset();
    packets.push_back(noLat);
    St0601Packet bad = packet(kUs0 + 4, 46.0, 7.0);
    bad.checksum = fmv::ChecksumVerdict::Mismatch;
    packets.push_back(bad);
    packets.push_back(packet(kUs0, 46.1, 7.0));   // a repeat of the first time
    packets.push_back(packet(kUs0 + 5, 46.2, 7.0));
    const KlvSamples s = samplesFromSt0601(packets);
    EXPECT_EQ(s.packets, 7u);
    ASSERT_EQ(s.samples.size(), 2u);
    EXPECT_EQ(s.withoutTime, 1u);
    EXPECT_EQ(s.withoutPosition, 2u);
    EXPECT_EQ(s.badChecksum, 1u);
    EXPECT_EQ(s.notAfterPrevious, 1u);
    EXPECT_EQ(samplesFromSt0601(packets, {.acceptBadChecksum = true}).samples.size(), 3u);
}

TEST(TrajectoryKlv, RawStreamFile) {
    std::vector<uint8_t> bytes{0xDE, 0xAD};   // garbage before the first key is skipped
    for (int i = 0; i < 20; ++i) {
        const auto b = fmv::encodeSt0601(packet(kUs0 + uint64_t(i) * 500'000, 46.0 + 1e-3 * i, 7.0));
        bytes.insert(bytes.end(), b.begin(), b.end());
    }
    std::vector<uint8_t> broken = fmv::encodeSt0601(packet(kUs0 + 99'000'000, 46.0, 7.0));
    broken.back() ^= 0xFF;   // the checksum's low byte
    bytes.insert(bytes.end(), broken.begin(), broken.end());
    const std::string path = (tempDir() / "flight.bin").string();
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    auto s = readKlvSamples(path);
    ASSERT_TRUE(s.ok()) << s.message();
    EXPECT_EQ(s->samples.size(), 20u);
    EXPECT_EQ(s->badChecksum, 1u);
    auto tr = readTrajectory(path);
    ASSERT_TRUE(tr.ok()) << tr.message();
    EXPECT_EQ(tr->sampleCount(), 20u);
    EXPECT_EQ(tr->timeRange().end - tr->timeRange().begin, 19 * TimeNs(500'000'000));
    EXPECT_NEAR(tr->pose(TimeNs(kUs0 + 1'250'000) * 1000)->latDeg, 46.0025, 1e-6);
}

TEST(TrajectoryKlv, StreamWithoutPosesSaysWhy) {
    St0601Packet p;
    p.precisionTimeUs = kUs0;   // a time, nothing else
    const auto b = fmv::encodeSt0601(p);
    const std::string path = (tempDir() / "empty.klv").string();
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
    auto s = readKlvSamples(path);
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.message(), "empty.klv: none of the 1 packets gives a platform pose (0 without a time stamp (tag 2), 1 without a position"))
        << s.message();
}

TEST(TrajectoryKlv, PoseCsvRowsKeepTheirLines) {
    const std::string path = writeText("poses.csv",
                                       "# exported\n"
                                       "Precision Time Stamp,Sensor Latitude,Sensor Longitude,Sensor True Altitude,Platform Heading Angle\n"
                                       "1700000000000000,46.0,7.0,1000,10\n"
                                       "1700000000500000,46.001,7.0,1001,11\n"
                                       "1700000000400000,46.002,7.0,1002,12\n");
    auto s = readPoseCsvSamples(path);
    ASSERT_TRUE(s.ok()) << s.message();
    ASSERT_EQ(s->samples.size(), 2u);   // the third steps back in time: left out
    EXPECT_EQ(s->samples[1].line, 4u);
    EXPECT_EQ(s->notAfterPrevious, 1u);
    EXPECT_EQ(s->samples[0].altRef, AltitudeRef::MeanSeaLevel);
    EXPECT_EQ(*s->samples[1].headingDeg, 11.0);
    // The same file as a trajectory CSV: the same names are understood, and the step back
    // is an error naming its line.
    auto csv = readTrajectory(path);
    ASSERT_FALSE(csv.ok());
    EXPECT_TRUE(contains(csv.message(), "poses.csv: line 5: time")) << csv.message();
    TrajectoryFileOptions o;
    o.format = TrajectoryFormat::PoseCsv;
    auto tr = readTrajectory(path, o);
    ASSERT_TRUE(tr.ok()) << tr.message();
    EXPECT_EQ(tr->sampleCount(), 2u);
}

TEST(TrajectoryKlv, ReferencePacket) {
    const auto path = sharedData("klv/DynamicOnlyMISMMSPacketData.bin");
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path << " (../shared/data is optional)";
    auto s = readKlvSamples(path.string());
    ASSERT_TRUE(s.ok()) << s.message();
    ASSERT_EQ(s->samples.size(), 1u);
    const TrajectorySample& a = s->samples[0];
    EXPECT_EQ(a.t, *parseIso8601("2009-01-12T22:08:22Z"));
    // The reference decode (tests/unit/KlvTest.cpp) to its stated 1e-9.
    EXPECT_NEAR(a.latDeg, 60.176822966978335, 1e-9);
    EXPECT_NEAR(a.lonDeg, 128.42675904204452, 1e-9);
    EXPECT_NEAR(*a.headingDeg, 159.97436484321355, 1e-9);
    EXPECT_NEAR(*a.pitchDeg, -0.43153172399060225, 1e-9);
    EXPECT_NEAR(*a.rollDeg, 3.4058656575212893, 1e-9);
    EXPECT_EQ(a.altRef, AltitudeRef::MeanSeaLevel);
    EXPECT_NEAR(a.alt, 14190.719462882429, 1e-7);
    auto tr = readTrajectory(path.string());
    ASSERT_TRUE(tr.ok()) << tr.message();
    EXPECT_NEAR(tr->pose(a.t + kNsPerSecond)->headingDeg, 159.97436484321355, 1e-9);   // one sample: held
}

}  // namespace
}  // namespace orbis::motion
