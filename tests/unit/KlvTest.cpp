// KLV and MISB ST 0601: BER lengths and tags, the two real packets in ../shared/data/klv against
// their published decode, every mapping at its range ends and error values (through the encoder,
// within one step of the integer), truncated, oversized and malformed packets, and random bytes.
#include "formats/fmv/Klv.h"
#include "formats/fmv/St0601.h"
#include "formats/fmv/St0601Encode.h"
#include "formats/fmv/St0601Fields.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

namespace orbis::fmv {
namespace {

namespace fs = std::filesystem;
using Buffer = std::vector<uint8_t>;

Buffer readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

fs::path sharedKlv(const char* name) { return fs::path(ORBIS_SHARED_DATA_DIR) / "klv" / name; }

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/// The smallest valid packet: a time stamp and the checksum.
St0601Packet minimalPacket() {
    St0601Packet p;
    p.precisionTimeUs = 1'700'000'000'000'000ull;
    return p;
}

// ---------------------------------------------------------------------------------- BER, keys

TEST(KlvBer, ShortFormHoldsUpTo127) {
    const Buffer b{0x7F};
    auto l = readBerLength(b, 0);
    ASSERT_TRUE(l.ok()) << l.message();
    EXPECT_EQ(l->value, 127u);
    EXPECT_EQ(l->bytes, 1u);
}

TEST(KlvBer, LongFormOneByte128) {
    const Buffer b{0x81, 0x80};
    auto l = readBerLength(b, 0);
    ASSERT_TRUE(l.ok()) << l.message();
    EXPECT_EQ(l->value, 128u);
    EXPECT_EQ(l->bytes, 2u);
}

TEST(KlvBer, LongFormOfEightBytesIsRead) {
    const Buffer b{0x88, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08};
    auto l = readBerLength(b, 0);
    ASSERT_TRUE(l.ok()) << l.message();
    EXPECT_EQ(l->value, 0x0102030405060708ull);
    EXPECT_EQ(l->bytes, 9u);
}

TEST(KlvBer, LongFormOfNineBytesIsRefused) {
    const Buffer b{0x89, 1, 2, 3, 4, 5, 6, 7, 8, 9};
    auto l = readBerLength(b, 0);
    ASSERT_FALSE(l.ok());
    EXPECT_TRUE(contains(l.message(), "long form of 9 bytes (at most 8)")) << l.message();
    EXPECT_FALSE(readBerLength(Buffer{0xFF}, 0).ok());
}

TEST(KlvBer, IndefiniteFormIsRefused) {
    auto l = readBerLength(Buffer{0x80, 0x00}, 0);
    ASSERT_FALSE(l.ok());
    EXPECT_TRUE(contains(l.message(), "indefinite")) << l.message();
}

TEST(KlvBer, LengthFieldCutByTheEndIsRefused) {
    EXPECT_FALSE(readBerLength(Buffer{0x82, 0x01}, 0).ok());
    EXPECT_FALSE(readBerLength(Buffer{}, 0).ok());
    EXPECT_FALSE(readBerLength(Buffer{0x05}, 1).ok());
}

TEST(KlvBer, LengthPastTheBufferIsRefused) {
    Buffer b(kSt0601Key.begin(), kSt0601Key.end());
    b.insert(b.end(), {0x81, 0x10, 1, 2, 3, 4, 5});   // 16 bytes claimed, 5 there
    auto t = readTriplet(b, 0, 1 << 20, 1000);
    ASSERT_FALSE(t.ok());
    EXPECT_TRUE(contains(t.message(), "packet at byte 1000: length 16 runs past the end of the data (5 bytes left)")) << t.message();
    // The largest 8-byte length, with nothing behind it.
    Buffer huge(kSt0601Key.begin(), kSt0601Key.end());
    huge.insert(huge.end(), {0x88, 0x7F, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF});
    EXPECT_FALSE(readTriplet(huge, 0, SIZE_MAX).ok());
}

TEST(KlvBer, EncoderWritesTheShortestFormAndReadsBack) {
    for (uint64_t v : {0ull, 1ull, 127ull, 128ull, 255ull, 256ull, 65535ull, 65536ull, 1ull << 32, ~0ull}) {
        Buffer b;
        appendBerLength(b, v);
        auto l = readBerLength(b, 0);
        ASSERT_TRUE(l.ok()) << v;
        EXPECT_EQ(l->value, v);
        EXPECT_EQ(l->bytes, b.size()) << v;
        std::size_t valueBytes = 0;
        for (uint64_t rest = v; rest != 0; rest >>= 8) ++valueBytes;
        EXPECT_EQ(b.size(), v < 128 ? 1u : 1u + valueBytes) << v;
    }
    Buffer forced;
    appendBerLengthLong(forced, 5, 1);
    EXPECT_EQ(forced, (Buffer{0x81, 0x05}));
}

TEST(KlvBerOid, TagsRoundTripAndOverLongOnesAreRefused) {
    for (uint32_t tag : {0u, 1u, 65u, 127u, 128u, 16383u, 16384u, (1u << 28) - 1}) {
        Buffer b;
        appendBerOid(b, tag);
        auto t = readBerOid(b, 0);
        ASSERT_TRUE(t.ok()) << tag;
        EXPECT_EQ(t->value, tag);
        EXPECT_EQ(t->bytes, b.size());
    }
    EXPECT_EQ([] { Buffer b; appendBerOid(b, 128); return b; }(), (Buffer{0x81, 0x00}));
    auto five = readBerOid(Buffer{0x81, 0x82, 0x83, 0x84, 0x05}, 0);
    ASSERT_FALSE(five.ok());
    EXPECT_TRUE(contains(five.message(), "longer than 4 bytes")) << five.message();
    EXPECT_FALSE(readBerOid(Buffer{0x81, 0x82}, 0).ok());   // continuation bit on the last byte
}

TEST(KlvKey, FoundAfterGarbageIgnoringTheVersionByte) {
    Buffer b{0x06, 0x0E, 0x2B, 0x34, 0xFF};   // a key's first bytes, then garbage
    const std::size_t at = b.size();
    b.insert(b.end(), kSt0601Key.begin(), kSt0601Key.end());
    b[at + 7] = 0x02;   // another registry version
    EXPECT_EQ(findKey(b, kSt0601Key), at);
    EXPECT_EQ(findKey(b, kSt0601Key, at + 1), b.size());
    EXPECT_EQ(findKey(Buffer(15, 0x06), kSt0601Key), 15u);
    EXPECT_EQ(findKey(Buffer{}, kSt0601Key), 0u);
}

TEST(KlvByteReader, NeverReadsPastTheEnd) {
    const Buffer b{1, 2, 3};
    ByteReader r(b);
    uint64_t v = 0;
    EXPECT_FALSE(r.uintBE(4, v));
    EXPECT_EQ(r.position(), 0u);
    EXPECT_TRUE(r.uintBE(2, v));
    EXPECT_EQ(v, 0x0102u);
    Bytes span;
    EXPECT_FALSE(r.take(2, span));
    EXPECT_TRUE(r.skip(1));
    uint8_t c;
    EXPECT_FALSE(r.u8(c));
    EXPECT_TRUE(r.atEnd());
}

// ------------------------------------------------------------------------- the real packets

// Published decode of the klvdata/MISB sample "DynamicOnlyMISMMSPacketData" (klvdata's and
// misb.js's test data). Tolerance: 1e-9 (degrees) and 1e-7 m, a few ulps of the mapping's
// arithmetic, which may be done in another order than the reference's.
TEST(KlvSt0601, DynamicOnlyPacketMatchesTheReferenceDecode) {
    const fs::path file = sharedKlv("DynamicOnlyMISMMSPacketData.bin");
    if (!fs::exists(file)) GTEST_SKIP() << "../shared/data is absent";
    const Buffer b = readBytes(file);
    auto r = decodeSt0601(b);
    ASSERT_TRUE(r.ok()) << r.message();
    const St0601Packet& p = *r;
    EXPECT_EQ(p.checksum, ChecksumVerdict::Valid);
    EXPECT_EQ(p.storedChecksum, 0xC850);
    EXPECT_EQ(p.computedChecksum, 0xC850);
    EXPECT_EQ(p.size, b.size());
    EXPECT_EQ(p.precisionTimeUs, 1231798102000000ull);   // 2009-01-12T22:08:22Z
    EXPECT_NEAR(*p.platformHeadingDeg, 159.97436484321355, 1e-9);
    EXPECT_NEAR(*p.platformPitchDeg, -0.43153172399060225, 1e-9);
    EXPECT_NEAR(*p.platformRollDeg, 3.4058656575212893, 1e-9);
    EXPECT_NEAR(*p.sensorLatitudeDeg, 60.176822966978335, 1e-9);
    EXPECT_NEAR(*p.sensorLongitudeDeg, 128.42675904204452, 1e-9);
    EXPECT_NEAR(*p.sensorTrueAltitude, 14190.719462882429, 1e-7);
    EXPECT_NEAR(*p.horizontalFovDeg, 144.5712977798123, 1e-9);
    EXPECT_NEAR(*p.verticalFovDeg, 152.64362554360264, 1e-9);
    EXPECT_NEAR(*p.sensorRelativeAzimuthDeg, 160.71921143697557, 1e-9);
    EXPECT_NEAR(*p.sensorRelativeElevationDeg, -168.79232483394085, 1e-9);
    EXPECT_EQ(*p.sensorRelativeRollDeg, 0.0);
    EXPECT_NEAR(*p.slantRange, 68590.98329874477, 1e-7);
    EXPECT_NEAR(*p.targetWidth, 722.8198672465096, 1e-7);
    EXPECT_NEAR(*p.frameCenterLatitudeDeg, -10.542388633146132, 1e-9);
    EXPECT_NEAR(*p.frameCenterLongitudeDeg, 29.15789012292302, 1e-9);
    EXPECT_NEAR(*p.frameCenterElevation, 3216.0372320134275, 1e-7);
    EXPECT_EQ(p.uasLsVersion, 6);
    EXPECT_TRUE(p.errorTags.empty());
    EXPECT_TRUE(p.otherTags.empty());
    EXPECT_TRUE(p.warnings.empty()) << p.warnings.front();
}

TEST(KlvSt0601, ReEncodingTheReferencePacketGivesItsBytesBack) {
    const fs::path file = sharedKlv("DynamicOnlyMISMMSPacketData.bin");
    if (!fs::exists(file)) GTEST_SKIP() << "../shared/data is absent";
    const Buffer b = readBytes(file);
    auto r = decodeSt0601(b);
    ASSERT_TRUE(r.ok()) << r.message();
    EXPECT_EQ(encodeSt0601(*r), b);   // the inverse mappings recover every integer exactly
}

TEST(KlvSt0601, WrongChecksumIsReportedAndTheValuesStillDecoded) {
    const fs::path file = sharedKlv("DynamicConstantMISMMSPacketData.bin");
    if (!fs::exists(file)) GTEST_SKIP() << "../shared/data is absent";
    const Buffer b = readBytes(file);
    auto r = decodeSt0601(b);
    ASSERT_TRUE(r.ok()) << r.message();
    const St0601Packet& p = *r;
    EXPECT_EQ(p.checksum, ChecksumVerdict::Mismatch);
    EXPECT_EQ(p.storedChecksum, 0xAA43);
    EXPECT_EQ(p.computedChecksum, 0x3E1E);   // the running sum over key .. 01 02
    EXPECT_EQ(p.missionId, "Mission 12");
    EXPECT_EQ(p.platformDesignation, "Predator");
    EXPECT_EQ(p.imageSourceSensor, "EO Nose");
    EXPECT_EQ(p.imageCoordinateSystem, "Geodetic WGS84");
    EXPECT_NEAR(*p.sensorLatitudeDeg, 60.176822966978335, 1e-9);
    EXPECT_NEAR(*p.platformHeadingDeg, 159.97436484321355, 1e-9);
    EXPECT_NEAR(*p.sensorRelativeRollDeg, 176.86543764939194, 1e-9);
    EXPECT_EQ(p.uasLsVersion, 6);
    // The nested ST 0102 security set (tag 48) and the MIIS core identifier (94) kept as raw.
    ASSERT_EQ(p.otherTags.size(), 2u);
    EXPECT_EQ(p.otherTags[0].tag, 48u);
    EXPECT_EQ(p.otherTags[0].bytes.size(), 28u);
    EXPECT_EQ(p.otherTags[0].bytes[0], 0x01);   // ST 0102 tag 1, classification
    EXPECT_EQ(p.otherTags[1].tag, 94u);
    EXPECT_EQ(p.otherTags[1].bytes.size(), 34u);
}

TEST(KlvSt0601, JsonLineNamesEveryFieldAndTheVerdict) {
    const fs::path file = sharedKlv("DynamicConstantMISMMSPacketData.bin");
    if (!fs::exists(file)) GTEST_SKIP() << "../shared/data is absent";
    auto r = decodeSt0601(readBytes(file));
    ASSERT_TRUE(r.ok()) << r.message();
    const std::string line = st0601JsonLine(*r, 0);
    EXPECT_EQ(line.find('\n'), std::string::npos);
    const auto j = nlohmann::json::parse(line);
    EXPECT_EQ(j["checksum"]["verdict"], "mismatch");
    EXPECT_EQ(j["checksum"]["stored"], "aa43");
    EXPECT_EQ(j["checksum"]["computed"], "3e1e");
    EXPECT_EQ(j["precisionTime"], "2009-01-12T22:08:22.000000Z");
    EXPECT_EQ(j["missionId"], "Mission 12");
    EXPECT_NEAR(j["sensorLatitudeDeg"].get<double>(), 60.176822966978335, 1e-9);
    EXPECT_EQ(j["otherTags"][0]["tag"], 48);
    EXPECT_EQ(j["otherTags"][0]["hex"].get<std::string>().substr(0, 4), "0101");
}

// ------------------------------------------------------------------------ every mapping

/// One field's encoding of `value` (after a time stamp), decoded again.
St0601Packet roundTrip(const detail::Field& f, std::optional<double> value, bool flagError = false) {
    St0601Packet p = minimalPacket();
    f.numberIn(p) = value;
    if (flagError) p.errorTags.push_back(f.tag);
    auto r = decodeSt0601(encodeSt0601(p));
    EXPECT_TRUE(r.ok()) << f.name << ": " << (r.ok() ? "" : r.message());
    EXPECT_EQ(r.ok() ? r->checksum : ChecksumVerdict::Missing, ChecksumVerdict::Valid) << f.name;
    return r.ok() ? *r : St0601Packet{};
}

bool isNumber(const detail::Field& f) {
    return f.kind == detail::Kind::Unsigned || f.kind == detail::Kind::Signed || f.kind == detail::Kind::Imapb;
}

// Tolerance: one step of the integer (the mapping's resolution), as ST 0601 allows.
TEST(KlvMapping, EveryNumberRoundTripsAtItsRangeEndsWithinOneStep) {
    for (const detail::Field& f : detail::st0601Fields()) {
        if (!isNumber(f)) continue;
        const double lsb = f.lsb(f.kind == detail::Kind::Imapb ? 4 : std::size_t(f.bytes));
        for (double x : {f.min, f.max, 0.5 * (f.min + f.max), f.min + 0.3 * (f.max - f.min), f.min + lsb, f.max - lsb}) {
            const St0601Packet p = roundTrip(f, x);
            const auto& v = f.numberIn(p);
            ASSERT_TRUE(v.has_value()) << f.name << " at " << x;
            EXPECT_NEAR(*v, x, lsb) << f.name;
            EXPECT_GE(*v, f.min - 1e-9 * std::abs(f.min)) << f.name;
            EXPECT_LE(*v, f.max + 1e-9 * std::abs(f.max)) << f.name;
            EXPECT_TRUE(p.errorTags.empty()) << f.name;
        }
    }
}

TEST(KlvMapping, SignedErrorValuesDecodeAsAbsentAndFlagged) {
    for (const detail::Field& f : detail::st0601Fields()) {
        if (f.kind != detail::Kind::Signed) continue;
        // The error value itself, written by hand: 0x8000 or 0x80000000.
        St0601Packet base = minimalPacket();
        base.otherTags.push_back({f.tag, Buffer(std::size_t(f.bytes), 0)});
        base.otherTags.back().bytes[0] = 0x80;
        auto r = decodeSt0601(encodeSt0601(base));
        ASSERT_TRUE(r.ok()) << r.message();
        EXPECT_FALSE(f.numberIn(*r).has_value()) << f.name;
        EXPECT_TRUE(r->hasError(f.tag)) << f.name;
        // Out of range and NaN are written as that error value.
        for (double bad : {f.max * 1.01, -f.max * 1.01, std::nan("")}) {
            const St0601Packet p = roundTrip(f, bad);
            EXPECT_FALSE(f.numberIn(p).has_value()) << f.name << " " << bad;
            EXPECT_TRUE(p.hasError(f.tag)) << f.name;
        }
        // An error flag without a value is written back as the error value.
        EXPECT_TRUE(roundTrip(f, std::nullopt, true).hasError(f.tag)) << f.name;
        // The most negative number is -max, one step above the error value.
        St0601Packet low = minimalPacket();
        low.otherTags.push_back({f.tag, Buffer(std::size_t(f.bytes), 0)});
        low.otherTags.back().bytes[0] = 0x80;
        low.otherTags.back().bytes.back() = 0x01;
        auto lr = decodeSt0601(encodeSt0601(low));
        ASSERT_TRUE(lr.ok());
        EXPECT_DOUBLE_EQ(*f.numberIn(*lr), f.min) << f.name;
    }
}

TEST(KlvMapping, UnsignedEndsAreTheRangeEnds) {
    for (const detail::Field& f : detail::st0601Fields()) {
        if (f.kind != detail::Kind::Unsigned) continue;
        for (uint8_t fill : {uint8_t(0x00), uint8_t(0xFF)}) {
            St0601Packet p = minimalPacket();
            p.otherTags.push_back({f.tag, Buffer(std::size_t(f.bytes), fill)});
            auto r = decodeSt0601(encodeSt0601(p));
            ASSERT_TRUE(r.ok());
            EXPECT_DOUBLE_EQ(*f.numberIn(*r), fill ? f.max : f.min) << f.name;
        }
        // Out of range clamps (these tags have no error value).
        const St0601Packet clamped = roundTrip(f, f.max + 1000.0);
        EXPECT_NEAR(*f.numberIn(clamped), f.max, 1e-9) << f.name;
    }
}

TEST(KlvMapping, ImapbSpecialAndOutOfRangeValuesAreErrors) {
    const detail::Field& f = *detail::findField(104);
    // Every length 1..8 round-trips the range ends within one step.
    for (std::size_t n = 1; n <= 8; ++n)
        for (double x : {-900.0, 0.0, 12345.678, 40000.0}) {
            const detail::Mapped m = detail::imapbDecode(f.min, f.max, detail::imapbEncode(f.min, f.max, x, n), n);
            ASSERT_TRUE(m.value.has_value()) << n << " " << x;
            EXPECT_NEAR(*m.value, x, f.lsb(n)) << n;
        }
    // ST 1201: with 4 bytes, IMAPB(-900, 40000) has bPow 16, sF 2^15, and zero lands on an integer.
    EXPECT_EQ(detail::imapbEncode(-900.0, 40000.0, 0.0, 4), 900u * 32768u);
    EXPECT_EQ(detail::imapbEncode(-900.0, 40000.0, -900.0, 4), 0u);
    for (uint64_t special : {0x80000000ull, 0xC8000000ull, 0xD0000000ull, 0xFFFFFFFFull})
        EXPECT_TRUE(detail::imapbDecode(-900.0, 40000.0, special, 4).error) << std::hex << special;
    // Above the range's top but below the special values: out of range.
    EXPECT_TRUE(detail::imapbDecode(-900.0, 40000.0, 0x7FFFFFFFull, 4).error);
    const St0601Packet nan = roundTrip(f, std::nan(""));
    EXPECT_FALSE(nan.sensorEllipsoidHeightExtended.has_value());
    EXPECT_TRUE(nan.hasError(104));
}

TEST(KlvMapping, TimestampAndVersionAreExact) {
    St0601Packet p;
    p.precisionTimeUs = ~0ull;
    p.uasLsVersion = 19;
    auto r = decodeSt0601(encodeSt0601(p));
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->precisionTimeUs, ~0ull);
    EXPECT_EQ(r->uasLsVersion, 19);
}

TEST(KlvMapping, FullPacketWithEveryFieldRoundTrips) {
    std::mt19937 rng(601);
    St0601Packet p = minimalPacket();
    p.missionId = "M-1";
    p.platformTailNumber = "N123";
    p.platformDesignation = "Synthetic";
    p.imageSourceSensor = "EO";
    p.imageCoordinateSystem = "Geodetic WGS84";
    p.uasLsVersion = 17;
    for (const detail::Field& f : detail::st0601Fields())
        if (isNumber(f)) f.numberIn(p) = std::uniform_real_distribution<double>(f.min, f.max)(rng);
    p.otherTags.push_back({73, {0x01, 0x02, 0x03}});   // an RVT set, verbatim
    for (int lengthBytes : {0, 1, 2, 8}) {
        const Buffer b = encodeSt0601(p, {.packetLengthBytes = lengthBytes});
        auto r = decodeSt0601(b);
        ASSERT_TRUE(r.ok()) << r.message();
        EXPECT_EQ(r->checksum, ChecksumVerdict::Valid);
        EXPECT_EQ(r->size, b.size());
        for (const detail::Field& f : detail::st0601Fields()) {
            if (!isNumber(f)) continue;
            EXPECT_NEAR(*f.numberIn(*r), *f.numberIn(p), f.lsb(f.kind == detail::Kind::Imapb ? 4 : std::size_t(f.bytes))) << f.name;
        }
        EXPECT_EQ(r->missionId, p.missionId);
        EXPECT_EQ(r->imageCoordinateSystem, p.imageCoordinateSystem);
        ASSERT_EQ(r->otherTags.size(), 1u);
        EXPECT_EQ(r->otherTags[0].bytes, p.otherTags[0].bytes);
        EXPECT_TRUE(r->warnings.empty()) << r->warnings.front();
    }
}

TEST(KlvSt0601, CornersPreferFullPrecisionThenCentrePlusOffset) {
    St0601Packet p;
    EXPECT_FALSE(p.corner(0).has_value());
    p.frameCenterLatitudeDeg = 10.0;
    p.frameCenterLongitudeDeg = 179.99;
    p.offsetCornerLatitudeDeg[1] = 0.05;
    p.offsetCornerLongitudeDeg[1] = 0.02;   // across the antimeridian
    ASSERT_TRUE(p.corner(1).has_value());
    EXPECT_NEAR(p.corner(1)->latDeg, 10.05, 1e-12);
    EXPECT_NEAR(p.corner(1)->lonDeg, -179.99, 1e-9);
    p.cornerLatitudeDeg[1] = 11.0;
    p.cornerLongitudeDeg[1] = 12.0;
    EXPECT_EQ(p.corner(1)->latDeg, 11.0);
    EXPECT_FALSE(p.corner(4).has_value());
    p.platformPitchDeg = 5.0;
    EXPECT_EQ(p.pitchDeg(), 5.0);
    p.platformPitchFullDeg = 45.0;
    EXPECT_EQ(p.pitchDeg(), 45.0);
}

// ------------------------------------------------------------- broken packets, random bytes

/// A packet with a bit of everything, for cutting and mutating.
Buffer samplePacket() {
    St0601Packet p = minimalPacket();
    p.missionId = "Sample";
    p.platformHeadingDeg = 12.5;
    p.sensorLatitudeDeg = 48.1;
    p.sensorLongitudeDeg = 11.6;
    p.sensorEllipsoidHeightExtended = 1234.5;
    p.cornerLatitudeDeg[0] = 48.0;
    p.otherTags.push_back({48, {0x01, 0x01, 0x01, 0x02, 0x01, 0x07}});
    return encodeSt0601(p, {.packetLengthBytes = 1});
}

TEST(KlvSt0601, EveryTruncationOfAValidPacketIsAClearError) {
    const Buffer full = samplePacket();
    ASSERT_TRUE(decodeSt0601(full).ok());
    for (std::size_t n = 0; n < full.size(); ++n) {
        const Buffer cut(full.begin(), full.begin() + std::ptrdiff_t(n));
        auto r = decodeSt0601(cut);
        ASSERT_FALSE(r.ok()) << n;
        if (n < 16) {
            EXPECT_TRUE(contains(r.message(), "not an ST 0601 packet")) << r.message();
        } else if (n >= 18) {
            EXPECT_TRUE(contains(r.message(), "truncated")) << n << ": " << r.message();
        }
    }
}

TEST(KlvSt0601, OversizedPacketsAreRefused) {
    // A length over kMaxSt0601PacketBytes with all its bytes there, and 2^63 with none.
    Buffer big(kSt0601Key.begin(), kSt0601Key.end());
    appendBerLengthLong(big, kMaxSt0601PacketBytes + 1, 3);
    big.resize(big.size() + kMaxSt0601PacketBytes + 1, 0x00);
    auto r = decodeSt0601(big);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.message(), "over the 1048576 bytes a packet may have")) << r.message();
    Buffer claim(kSt0601Key.begin(), kSt0601Key.end());
    appendBerLengthLong(claim, 1ull << 63, 8);
    EXPECT_FALSE(decodeSt0601(claim).ok());
}

TEST(KlvSt0601, ItemRunningPastTheSetIsAnErrorNamingTheTag) {
    Buffer b(kSt0601Key.begin(), kSt0601Key.end());
    b.insert(b.end(), {0x06, 0x41, 0x01, 0x06, 0x0D, 0x09, 0x00});   // 6 bytes: tag 65, then tag 13 claims 9 bytes, 1 there
    auto r = decodeSt0601(b, 100);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.message(), "tag 13 at byte 120: length 9 runs past the end of the set (1 bytes left)")) << r.message();
}

TEST(KlvSt0601, DuplicateTagsWarnAndKeepTheFirst) {
    St0601Packet p = minimalPacket();
    p.platformHeadingDeg = 90.0;
    p.otherTags.push_back({5, {0x00, 0x00}});   // heading 0, again
    auto r = decodeSt0601(encodeSt0601(p));
    ASSERT_TRUE(r.ok());
    EXPECT_NEAR(*r->platformHeadingDeg, 90.0, 0.01);
    ASSERT_EQ(r->warnings.size(), 1u);
    EXPECT_TRUE(contains(r->warnings[0], "tag 5 at byte")) << r->warnings[0];
    EXPECT_TRUE(contains(r->warnings[0], "appears again")) << r->warnings[0];
}

TEST(KlvSt0601, ValueOfTheWrongSizeIsFlaggedAndKeptRaw) {
    St0601Packet p = minimalPacket();
    p.otherTags.push_back({13, {0x12, 0x34, 0x56}});   // latitude needs 4 bytes
    auto r = decodeSt0601(encodeSt0601(p));
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(r->sensorLatitudeDeg.has_value());
    EXPECT_TRUE(r->hasError(13));
    ASSERT_EQ(r->otherTags.size(), 1u);
    EXPECT_EQ(r->otherTags[0].bytes.size(), 3u);
    ASSERT_FALSE(r->warnings.empty());
    EXPECT_TRUE(contains(r->warnings[0], "3 bytes, ST 0601 gives it 4")) << r->warnings[0];
}

TEST(KlvSt0601, MissingOrMisplacedChecksumIsReported) {
    const Buffer set{0x41, 0x01, 0x06};   // tag 65 only
    Buffer noChecksum(kSt0601Key.begin(), kSt0601Key.end());
    noChecksum.push_back(uint8_t(set.size()));
    noChecksum.insert(noChecksum.end(), set.begin(), set.end());
    auto r = decodeSt0601(noChecksum);
    ASSERT_TRUE(r.ok()) << r.message();
    EXPECT_EQ(r->checksum, ChecksumVerdict::Missing);
    EXPECT_TRUE(std::any_of(r->warnings.begin(), r->warnings.end(), [](const std::string& w) { return contains(w, "no checksum"); }));

    // Checksum first, then tag 65: it covers the bytes up to its own length byte, and it is not last.
    Buffer early(kSt0601Key.begin(), kSt0601Key.end());
    early.insert(early.end(), {0x07, 0x01, 0x02});
    const uint16_t sum = st0601Checksum(early);
    early.insert(early.end(), {uint8_t(sum >> 8), uint8_t(sum), 0x41, 0x01, 0x06});
    auto e = decodeSt0601(early);
    ASSERT_TRUE(e.ok()) << e.message();
    EXPECT_EQ(e->checksum, ChecksumVerdict::Valid);
    EXPECT_TRUE(std::any_of(e->warnings.begin(), e->warnings.end(), [](const std::string& w) { return contains(w, "not the last item"); }));
}

TEST(KlvSt0601, ChecksumIsTheBigEndianRunningSum) {
    EXPECT_EQ(st0601Checksum(Buffer{}), 0);
    EXPECT_EQ(st0601Checksum(Buffer{0x12}), 0x1200);
    EXPECT_EQ(st0601Checksum(Buffer{0x12, 0x34, 0x01}), 0x1334);
    EXPECT_EQ(st0601Checksum(Buffer{0xFF, 0xFF, 0x00, 0x02}), 0x0001);   // modulo 2^16
}

/// What any decoded packet must satisfy, whatever bytes it came from.
void expectSane(const St0601Packet& p, std::size_t bufferSize) {
    EXPECT_LE(p.size, bufferSize);
    std::size_t raw = 0;
    for (const RawTag& t : p.otherTags) raw += t.bytes.size();
    EXPECT_LE(raw, p.size);
    for (const detail::Field& f : detail::st0601Fields()) {
        if (!isNumber(f)) continue;
        if (const auto& v = f.numberIn(p)) {
            EXPECT_TRUE(std::isfinite(*v)) << f.name;
            const double lsb = f.lsb(8);
            EXPECT_GE(*v, f.min - lsb - 1e-9) << f.name;
            EXPECT_LE(*v, f.max + lsb + 1e-9) << f.name;
        }
    }
    EXPECT_NO_THROW(nlohmann::json::parse(st0601JsonLine(p, 0)));
}

// Seeded: a few thousand buffers of pure noise, of noise behind a valid key, and of a valid
// packet with bytes flipped. Nothing may throw or crash; whatever decodes must be sane. (Reads
// past the buffer would need ASan to see; the decoder only reads through bounds-checked spans.)
TEST(KlvSt0601, RandomBytesNeverCrashAndDecodeSanely) {
    std::mt19937 rng(20240601);
    const Buffer valid = samplePacket();
    std::size_t decoded = 0;
    for (int i = 0; i < 3000; ++i) {
        const std::size_t size = std::uniform_int_distribution<std::size_t>(0, 400)(rng);
        Buffer b(size);
        for (auto& c : b) c = uint8_t(rng());
        switch (i % 3) {
        case 0: break;
        case 1:
            if (b.size() >= 16) std::copy(kSt0601Key.begin(), kSt0601Key.end(), b.begin());
            break;
        default:
            b = valid;
            for (int k = 0; k < 1 + i % 7; ++k) b[std::uniform_int_distribution<std::size_t>(16, b.size() - 1)(rng)] = uint8_t(rng());
            if (i % 2) b.resize(std::uniform_int_distribution<std::size_t>(b.size() / 2, b.size() + 8)(rng), 0x00);
        }
        // A copy of exactly the right size on the heap: a read past it is a read past an allocation.
        const std::unique_ptr<uint8_t[]> exact(new uint8_t[b.size() + 1]);
        std::copy(b.begin(), b.end(), exact.get());
        const Bytes span(exact.get(), b.size());
        Result<St0601Packet> r = makeError("");
        ASSERT_NO_THROW(r = decodeSt0601(span));
        if (r.ok()) {
            ++decoded;
            expectSane(*r, b.size());
        } else {
            EXPECT_FALSE(r.message().empty());
        }
    }
    EXPECT_GT(decoded, 100u);   // the mutated packets mostly still decode
}

}  // namespace
}  // namespace orbis::fmv
