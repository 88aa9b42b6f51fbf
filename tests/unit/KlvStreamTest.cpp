// Packet sources without video: raw KLV streams (.bin/.klv) with garbage and broken packets, the
// real files in ../shared/data/klv, and pose CSV sidecars (column names, units, errors that name
// the line and the column).
#include "formats/fmv/KlvFile.h"
#include "formats/fmv/PoseCsv.h"
#include "formats/fmv/St0601Encode.h"
#include "tests/support/ProcessTempDir.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

namespace orbis::fmv {
namespace {

namespace fs = std::filesystem;
using Buffer = std::vector<uint8_t>;

fs::path tempDir() { return test::processTempDir("orbis-klv"); }

fs::path writeFile(const std::string& name, const void* data, std::size_t size) {
    const fs::path p = tempDir() / name;
    std::ofstream(p, std::ios::binary).write(static_cast<const char*>(data), std::streamsize(size));
    return p;
}
fs::path writeFile(const std::string& name, const Buffer& b) { return writeFile(name, b.data(), b.size()); }
fs::path writeText(const std::string& name, const std::string& s) { return writeFile(name, s.data(), s.size()); }

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

Buffer packetAt(double latDeg, uint64_t timeUs) {
    St0601Packet p;
    p.precisionTimeUs = timeUs;
    p.sensorLatitudeDeg = latDeg;
    p.sensorLongitudeDeg = 7.0;
    return encodeSt0601(p);
}

void append(Buffer& b, const Buffer& more) { b.insert(b.end(), more.begin(), more.end()); }

// --------------------------------------------------------------------------------- streams

TEST(KlvStream, ResynchronisesOnTheKeyAfterGarbage) {
    const Buffer a = packetAt(1.0, 1), b = packetAt(2.0, 2), c = packetAt(3.0, 3);
    Buffer s{0xDE, 0xAD, 0x06, 0x0E};   // 4 bytes of garbage, the last two a key's start
    append(s, a);
    append(s, Buffer(5, 0x06));
    append(s, b);
    append(s, c);
    append(s, Buffer{0x06, 0x0E, 0x2B});   // a key cut by the end
    const KlvStream st = decodeKlvStream(s);
    ASSERT_EQ(st.records.size(), 3u);
    EXPECT_EQ(st.decodedCount(), 3u);
    EXPECT_EQ(st.records[0].offset, 4u);
    EXPECT_EQ(st.records[1].offset, 4u + a.size() + 5u);
    EXPECT_EQ(st.records[2].offset, st.records[1].offset + b.size());
    EXPECT_NEAR(*st.records[2].packet->sensorLatitudeDeg, 3.0, 1e-7);
    ASSERT_EQ(st.gaps.size(), 3u);
    EXPECT_EQ(st.gaps[0].offset, 0u);
    EXPECT_EQ(st.gaps[0].bytes, 4u);
    EXPECT_EQ(st.gaps[1].bytes, 5u);
    EXPECT_EQ(st.gaps[2].bytes, 3u);
}

TEST(KlvStream, BrokenPacketIsReportedAndTheNextOneStillRead) {
    Buffer s = packetAt(1.0, 1);
    Buffer bad = packetAt(2.0, 2);
    bad[16] = 0x89;   // a 9-byte BER length
    const std::size_t badAt = s.size();
    append(s, bad);
    append(s, packetAt(3.0, 3));
    const KlvStream st = decodeKlvStream(s);
    ASSERT_EQ(st.records.size(), 3u);
    EXPECT_FALSE(st.records[1].packet.has_value());
    EXPECT_EQ(st.records[1].offset, badAt);
    EXPECT_TRUE(contains(st.records[1].error, "packet at byte " + std::to_string(badAt) + ": BER length: long form of 9 bytes"))
        << st.records[1].error;
    ASSERT_TRUE(st.records[2].packet.has_value());
    EXPECT_NEAR(*st.records[2].packet->sensorLatitudeDeg, 3.0, 1e-7);
    EXPECT_EQ(st.gaps.size(), 1u);   // the broken packet's body
}

TEST(KlvStream, PacketCutByTheEndOfTheStreamIsTruncated) {
    Buffer s = packetAt(1.0, 1);
    const Buffer b = packetAt(2.0, 2);
    s.insert(s.end(), b.begin(), b.begin() + 30);
    const KlvStream st = decodeKlvStream(s);
    ASSERT_EQ(st.records.size(), 2u);
    EXPECT_TRUE(st.records[0].packet.has_value());
    EXPECT_TRUE(contains(st.records[1].error, "truncated")) << st.records[1].error;
}

TEST(KlvStream, CorruptChecksumsAreCountedNotDropped) {
    Buffer s = packetAt(1.0, 1);
    s.back() ^= 0xFF;
    append(s, packetAt(2.0, 2));
    const KlvStream st = decodeKlvStream(s);
    EXPECT_EQ(st.decodedCount(), 2u);
    EXPECT_EQ(st.checksumErrors(), 1u);
}

TEST(KlvStream, RandomStreamsStayWithinTheirBytes) {
    std::mt19937 rng(7);
    const Buffer good = packetAt(45.0, 99);
    for (int i = 0; i < 500; ++i) {
        Buffer s;
        while (s.size() < 2000) {
            if (rng() % 3 == 0) append(s, good);
            else
                for (int k = int(rng() % 64); k > 0; --k) s.push_back(uint8_t(rng() % 4 == 0 ? 0x06 : rng()));
            if (rng() % 5 == 0) s.resize(s.size() - std::min<std::size_t>(s.size(), rng() % 20));
        }
        KlvStream st;
        ASSERT_NO_THROW(st = decodeKlvStream(s));
        uint64_t last = 0, covered = 0;
        for (const KlvRecord& r : st.records) {
            EXPECT_GE(r.offset, last);
            EXPECT_LT(r.offset, s.size());
            last = r.offset;
            covered += r.packet ? r.packet->size : 16;
            EXPECT_NE(r.packet.has_value(), !r.error.empty());
        }
        for (const KlvGap& g : st.gaps) covered += g.bytes;
        EXPECT_EQ(covered, s.size()) << "records and gaps tile the stream";
    }
}

// ------------------------------------------------------------------------------------ files

TEST(KlvFile, RealPacketsReadWithTheirVerdicts) {
    const fs::path dir = fs::path(ORBIS_SHARED_DATA_DIR) / "klv";
    if (!fs::exists(dir / "DynamicOnlyMISMMSPacketData.bin")) GTEST_SKIP() << "../shared/data is absent";
    auto good = readKlvFile((dir / "DynamicOnlyMISMMSPacketData.bin").string());
    ASSERT_TRUE(good.ok()) << good.message();
    ASSERT_EQ(good->records.size(), 1u);
    EXPECT_EQ(good->records[0].offset, 0u);
    EXPECT_EQ(good->records[0].packet->checksum, ChecksumVerdict::Valid);
    EXPECT_TRUE(good->gaps.empty());
    auto bad = readKlvFile((dir / "DynamicConstantMISMMSPacketData.bin").string());
    ASSERT_TRUE(bad.ok()) << bad.message();
    EXPECT_EQ(bad->checksumErrors(), 1u);
    EXPECT_TRUE(looksLikeKlv((dir / "DynamicOnlyMISMMSPacketData.bin").string()));
}

TEST(KlvFile, UnreadableEmptyOrKeylessFilesAreErrorsNamingTheFile) {
    auto missing = readKlvFile("/nonexistent/packets.bin");
    ASSERT_FALSE(missing.ok());
    EXPECT_TRUE(contains(missing.message(), "/nonexistent/packets.bin: cannot read")) << missing.message();
    const fs::path empty = writeText("empty.bin", "");
    auto e = readKlvFile(empty.string());
    ASSERT_FALSE(e.ok());
    EXPECT_TRUE(contains(e.message(), empty.string() + ": empty file")) << e.message();
    const fs::path text = writeText("text.bin", "hello, this is not KLV at all");
    auto t = readKlvFile(text.string());
    ASSERT_FALSE(t.ok());
    EXPECT_TRUE(contains(t.message(), text.string() + ": no MISB ST 0601 packet (key 060e2b34020b01010e01030101000000) in 29 bytes"))
        << t.message();
}

TEST(KlvFile, DetectedByExtensionOrByTheKey) {
    const Buffer p = packetAt(1.0, 1);
    EXPECT_TRUE(looksLikeKlv(writeFile("noext", p).string()));
    EXPECT_TRUE(looksLikeKlv(writeText("x.KLV", "x").string()));
    EXPECT_FALSE(looksLikeKlv(writeText("x.dat", "not klv, but long enough").string()));
    EXPECT_FALSE(looksLikeKlv("/nonexistent/x.dat"));
}

// -------------------------------------------------------------------------------- pose CSV

TEST(KlvPoseCsv, ReadsLiberalColumnNamesAndUnits) {
    const std::string text =
        "\xEF\xBB\xBF# exported by an older tool\n"
        "Time (s), Sensor Latitude (deg), sensor_lon, Alt_ft, Platform Heading, pitch, roll,"
        " Sensor Rel Az, sensor_rel_el_rad, Sensor Rel Roll, HFOV, VFOV, comment\n"
        "0.0, 48.5, 11.25, 1000, 90, 2, -3, 10, -0.5, 0, 30, 20, \"a, quoted, note\"\n"
        "\n"
        "0.04, 48.5001, 11.2501, 1001, 90.5, , nan, 11, -0.51, 0, 30, 20, x\n";
    auto csv = parsePoseCsv(text, "flight.csv");
    ASSERT_TRUE(csv.ok()) << csv.message();
    ASSERT_EQ(csv->samples.size(), 2u);
    EXPECT_EQ(csv->timeUnit, "s");
    EXPECT_EQ(csv->ignored, std::vector<std::string>{"comment"});
    const St0601Packet& a = csv->samples[0].pose;
    EXPECT_EQ(csv->samples[0].line, 3u);
    EXPECT_EQ(a.precisionTimeUs, 0u);
    EXPECT_EQ(a.sensorLatitudeDeg, 48.5);
    EXPECT_EQ(a.sensorLongitudeDeg, 11.25);
    EXPECT_NEAR(*a.sensorTrueAltitude, 304.8, 1e-9);   // feet converted
    EXPECT_EQ(a.platformHeadingDeg, 90.0);
    EXPECT_EQ(a.pitchDeg(), 2.0);
    EXPECT_EQ(a.rollDeg(), -3.0);
    EXPECT_EQ(a.sensorRelativeAzimuthDeg, 10.0);
    EXPECT_NEAR(*a.sensorRelativeElevationDeg, -0.5 * 180.0 / std::numbers::pi, 1e-12);   // radians converted
    EXPECT_EQ(a.horizontalFovDeg, 30.0);
    EXPECT_EQ(a.verticalFovDeg, 20.0);
    const St0601Packet& b = csv->samples[1].pose;
    EXPECT_EQ(csv->samples[1].line, 5u);
    EXPECT_EQ(b.precisionTimeUs, 40000u);
    EXPECT_FALSE(b.pitchDeg().has_value());   // empty cell
    EXPECT_FALSE(b.rollDeg().has_value());    // "nan"
}

TEST(KlvPoseCsv, TimesAsIso8601OrMicrosecondsAndOtherSeparators) {
    auto iso = parsePoseCsv("timestamp;lat;lon;hae\n2009-01-12T22:08:22.5Z;1;2;3\n", "a.csv");
    ASSERT_TRUE(iso.ok()) << iso.message();
    EXPECT_EQ(iso->timeUnit, "iso8601");
    EXPECT_EQ(iso->samples[0].pose.precisionTimeUs, 1231798102500000ull);
    EXPECT_EQ(iso->samples[0].pose.sensorEllipsoidHeight, 3.0);
    auto us = parsePoseCsv("time\tlatitude\tlongitude\taltitude\n1231798102000000\t1\t2\t3\n", "b.csv");
    ASSERT_TRUE(us.ok()) << us.message();
    EXPECT_EQ(us->timeUnit, "us");
    EXPECT_EQ(us->samples[0].pose.precisionTimeUs, 1231798102000000ull);
    auto ms = parsePoseCsv("time_ms,lat,lon,alt\n1500,1,2,3\n", "c.csv");
    ASSERT_TRUE(ms.ok()) << ms.message();
    EXPECT_EQ(ms->samples[0].pose.precisionTimeUs, 1500000u);
}

TEST(KlvPoseCsv, BadValueNamesTheFileLineAndColumn) {
    auto csv = parsePoseCsv("time,lat,lon,alt\n0,1,2,3\n1,1,two,3\n", "pose.csv");
    ASSERT_FALSE(csv.ok());
    EXPECT_EQ(csv.message(), "pose.csv: line 3, column 3 (lon): 'two' is not a number");
    auto t = parsePoseCsv("time,lat,lon,alt\nnoon,1,2,3\n", "pose.csv");
    ASSERT_FALSE(t.ok());
    EXPECT_TRUE(contains(t.message(), "pose.csv: line 2, column 1 (time): 'noon' is neither a number nor an ISO 8601 time")) << t.message();
    auto wide = parsePoseCsv("time,lat,lon,alt\n0,1,2,3,4\n", "pose.csv");
    ASSERT_FALSE(wide.ok());
    EXPECT_EQ(wide.message(), "pose.csv: line 2: 5 cells, the header has 4");
    auto early = parsePoseCsv("time,lat,lon,alt\n-5,1,2,3\n", "pose.csv");
    ASSERT_FALSE(early.ok());
    EXPECT_TRUE(contains(early.message(), "before 1970")) << early.message();
}

TEST(KlvPoseCsv, MissingOrDuplicateColumnsAreNamed) {
    auto none = parsePoseCsv("time,heading,pitch\n0,1,2\n", "p.csv");
    ASSERT_FALSE(none.ok());
    EXPECT_TRUE(contains(none.message(), "p.csv: line 1: no column for latitude")) << none.message();
    EXPECT_TRUE(contains(none.message(), "longitude")) << none.message();
    EXPECT_TRUE(contains(none.message(), "altitude or height")) << none.message();
    EXPECT_FALSE(contains(none.message(), "time (")) << none.message();
    auto twice = parsePoseCsv("time,lat,Sensor Latitude,lon,alt\n", "p.csv");
    ASSERT_FALSE(twice.ok());
    EXPECT_TRUE(contains(twice.message(), "columns 2 (lat) and 3 (Sensor Latitude) give the same value")) << twice.message();
    auto empty = parsePoseCsv("# only a comment\n\n", "p.csv");
    ASSERT_FALSE(empty.ok());
    EXPECT_TRUE(contains(empty.message(), "p.csv: no header line")) << empty.message();
}

TEST(KlvPoseCsv, FilesAreReadAndRecognised) {
    const fs::path good = writeText("pose.csv", "t,lat,lon,alt\n0,1,2,3\n1,1,2,3\n");
    auto csv = readPoseCsv(good.string());
    ASSERT_TRUE(csv.ok()) << csv.message();
    EXPECT_EQ(csv->samples.size(), 2u);
    EXPECT_TRUE(looksLikePoseCsv(good.string()));
    EXPECT_FALSE(looksLikePoseCsv(writeText("other.csv", "name,population\nx,1\n").string()));
    auto missing = readPoseCsv("/nonexistent/pose.csv");
    ASSERT_FALSE(missing.ok());
    EXPECT_TRUE(contains(missing.message(), "/nonexistent/pose.csv: cannot read")) << missing.message();
}

}  // namespace
}  // namespace orbis::fmv
