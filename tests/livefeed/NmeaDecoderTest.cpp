// The NMEA stream decoder (NmeaDecoder.h): framing, bounds, dates, merging of an epoch's
// sentences, and the writer's round trip.

#include "formats/livefeed/NmeaDecoder.h"
#include "formats/livefeed/NmeaWriter.h"
#include "tests/livefeed/FeedServer.h"

#include <gtest/gtest.h>

#include <random>

namespace orbis::livefeed {
namespace {

using Clock = std::chrono::steady_clock;

TimeNs at(const char* iso) {
    const Result<TimeNs> t = parseIso8601(iso);
    EXPECT_TRUE(t.ok()) << iso;
    return t.ok() ? *t : 0;
}

std::vector<Fix> feed(NmeaDecoder& d, std::string_view bytes) {
    std::vector<Fix> out;
    d.feed(bytes, Clock::now(), out);
    return out;
}

std::vector<Fix> flush(NmeaDecoder& d) {
    std::vector<Fix> out;
    d.flush(Clock::now(), out);
    return out;
}

std::string gga(const char* time, int quality = 1) {
    return nmeaSentence(std::string("GPGGA,") + time + ",4807.038,N,01131.000,E," + std::to_string(quality) + ",08,0.9,545.4,M,46.9,M,,");
}
std::string rmc(const char* time, const char* date, char status = 'A') {
    return nmeaSentence(std::string("GPRMC,") + time + "," + status + ",4807.038,N,01131.000,E,022.4,084.4," + date + ",003.1,W");
}
std::string vtg(double knots) {
    char body[96];
    std::snprintf(body, sizeof body, "GPVTG,084.4,T,,M,%.3f,N,%.3f,K,A", knots, knots * 1.852);
    return nmeaSentence(body);
}

std::string track(const std::vector<Fix>& fixes) {
    const NmeaWriter writer;
    std::string s;
    for (const Fix& f : fixes) s += writer.epoch(f);
    return s;
}

TEST(NmeaDecoder, MergesGgaRmcAndVtgOfOneEpochIntoOneFix) {
    NmeaDecoder d;
    EXPECT_TRUE(feed(d, gga("123519") + rmc("123519", "230394") + vtg(22.4)).empty()) << "first epoch: held until it is known complete";
    const std::vector<Fix> fixes = flush(d);
    ASSERT_EQ(fixes.size(), 1u);
    const Fix& f = fixes[0];
    EXPECT_EQ(f.time, at("1994-03-23T12:35:19Z"));
    EXPECT_NEAR(f.latDeg, 48.1173, 1e-9);
    EXPECT_NEAR(f.lonDeg, 11.0 + 31.0 / 60.0, 1e-9);
    EXPECT_NEAR(*f.altitudeMsl, 545.4, 1e-9);
    EXPECT_NEAR(*f.heightEllipsoid, 545.4 + 46.9, 1e-9);   // GGA altitude + geoid separation
    EXPECT_NEAR(*f.speedMps, 22.4 * 1.852 / 3.6, 1.5e-4);   // VTG's km/h (preferred), written to 0.001 km/h
    EXPECT_NEAR(*f.courseDeg, 84.4, 1e-9);
    EXPECT_EQ(f.quality, 1);
    EXPECT_EQ(f.satellites, 8);
    EXPECT_NEAR(*f.hdop, 0.9, 1e-9);
    EXPECT_FALSE(f.headingDeg);
    EXPECT_EQ(f.format, FixFormat::Nmea);
    EXPECT_TRUE(flush(d).empty()) << "one fix per epoch";
    EXPECT_EQ(d.counters().messagesOk, 3u);
    EXPECT_EQ(d.counters().fixes, 1u);
}

TEST(NmeaDecoder, OnceLearntEachEpochGoesOutOnItsLastSentence) {
    const std::vector<Fix> fixes = test::syntheticTrack(5, at("2026-03-20T08:00:00Z"), kNsPerSecond);
    const NmeaWriter w;
    NmeaDecoder d;
    EXPECT_TRUE(feed(d, w.epoch(fixes[0])).empty());
    EXPECT_EQ(feed(d, w.gga(fixes[1])).size(), 1u) << "epoch 0 ends when epoch 1 begins";
    for (std::size_t i = 1; i < fixes.size(); ++i) {
        if (i > 1) {
            EXPECT_TRUE(feed(d, w.gga(fixes[i])).empty());
        }
        EXPECT_TRUE(feed(d, w.rmc(fixes[i])).empty()) << "VTG still expected in epoch " << i;
        const std::vector<Fix> out = feed(d, w.vtg(fixes[i]));
        ASSERT_EQ(out.size(), 1u) << "epoch " << i;
        EXPECT_EQ(out[0].time, fixes[i].time);
    }
    EXPECT_TRUE(flush(d).empty());
}

TEST(NmeaDecoder, FixQualityZeroAndVoidRmcGiveNoFix) {
    NmeaDecoder d;
    std::vector<Fix> all;
    for (const char* t : {"120000", "120001", "120002"}) {
        const std::vector<Fix> out = feed(d, gga(t, 0) + rmc(t, "190326", 'V'));
        all.insert(all.end(), out.begin(), out.end());
    }
    const std::vector<Fix> rest = flush(d);
    all.insert(all.end(), rest.begin(), rest.end());
    EXPECT_TRUE(all.empty());
    EXPECT_EQ(d.counters().messagesOk, 6u);
    EXPECT_EQ(d.counters().noFix, 6u);
    EXPECT_EQ(d.counters().fixes, 0u);
}

TEST(NmeaDecoder, GgaTakesTheDateOfTheLastRmc) {
    DecoderOptions options;
    options.referenceTime = at("2000-01-01T00:00:00Z");   // must not be used once an RMC gave a date
    NmeaDecoder d(options);
    std::vector<Fix> out = feed(d, rmc("100000", "190326") + gga("100001") + gga("100002"));
    const std::vector<Fix> rest = flush(d);
    out.insert(out.end(), rest.begin(), rest.end());
    ASSERT_EQ(out.size(), 3u);
    EXPECT_EQ(out[0].time, at("2026-03-19T10:00:00Z"));
    EXPECT_EQ(out[1].time, at("2026-03-19T10:00:01Z"));
    EXPECT_EQ(out[2].time, at("2026-03-19T10:00:02Z"));
}

TEST(NmeaDecoder, GgaAfterMidnightRollsTheRmcDateOver) {
    NmeaDecoder d;
    std::vector<Fix> out = feed(d, rmc("235959.000", "190326") + gga("235959.500") + gga("000000.000") + gga("000000.500"));
    const std::vector<Fix> rest = flush(d);
    out.insert(out.end(), rest.begin(), rest.end());
    ASSERT_EQ(out.size(), 4u);
    EXPECT_EQ(out[0].time, at("2026-03-19T23:59:59Z"));
    EXPECT_EQ(out[1].time, at("2026-03-19T23:59:59.5Z"));
    EXPECT_EQ(out[2].time, at("2026-03-20T00:00:00Z"));
    EXPECT_EQ(out[3].time, at("2026-03-20T00:00:00.5Z"));
}

TEST(NmeaDecoder, GgaBeforeAnyRmcTakesTheReferenceDateAndItsSideOfMidnight) {
    DecoderOptions options;
    options.referenceTime = at("2026-03-20T08:00:00Z");
    NmeaDecoder same(options);
    feed(same, gga("080001"));
    ASSERT_EQ(flush(same).at(0).time, at("2026-03-20T08:00:01Z"));

    options.referenceTime = at("2026-03-20T00:00:05Z");   // a GGA from just before midnight
    NmeaDecoder before(options);
    feed(before, gga("235958"));
    EXPECT_EQ(flush(before).at(0).time, at("2026-03-19T23:59:58Z"));

    options.referenceTime = at("2026-03-19T23:59:55Z");   // a GGA from just after midnight
    NmeaDecoder after(options);
    feed(after, gga("000002"));
    EXPECT_EQ(flush(after).at(0).time, at("2026-03-20T00:00:02Z"));
}

TEST(NmeaDecoder, RmcDateWinsOverTheReferenceWithinItsEpoch) {
    DecoderOptions options;
    options.referenceTime = at("2000-01-01T12:00:00Z");
    NmeaDecoder d(options);
    feed(d, gga("123519") + rmc("123519", "190326"));
    EXPECT_EQ(flush(d).at(0).time, at("2026-03-19T12:35:19Z"));
}

TEST(NmeaDecoder, BadChecksumIsDroppedAndCounted) {
    const std::vector<Fix> fixes = test::syntheticTrack(10, at("2026-03-20T08:00:00Z"), kNsPerSecond / 10);
    const NmeaWriter w;
    std::string stream;
    for (std::size_t i = 0; i < fixes.size(); ++i) {
        std::string g = w.gga(fixes[i]), r = w.rmc(fixes[i]);
        if (i == 5) {   // one changed digit in each: both fail their checksum
            g[20] = g[20] == '1' ? '2' : '1';
            r[20] = r[20] == '1' ? '2' : '1';
        }
        stream += g + r + w.vtg(fixes[i]);
    }
    NmeaDecoder d;
    std::vector<Fix> out = feed(d, stream);
    const std::vector<Fix> rest = flush(d);
    out.insert(out.end(), rest.begin(), rest.end());
    EXPECT_EQ(d.counters().badChecksum, 2u);
    EXPECT_NE(d.counters().lastError.find("checksum"), std::string::npos) << d.counters().lastError;
    ASSERT_EQ(out.size(), 9u);
    for (std::size_t i = 0, j = 0; i < fixes.size(); ++i) {
        if (i == 5) continue;
        EXPECT_EQ(out[j].time, fixes[i].time) << "epoch " << i;
        // The orphaned VTG of epoch 5 must not shift later VTGs onto the wrong epoch.
        EXPECT_NEAR(*out[j].speedMps, *fixes[i].speedMps, 2e-4) << "epoch " << i;
        ++j;
    }
}

TEST(NmeaDecoder, EndlessLineIsDroppedWithoutGrowing) {
    NmeaDecoder d;
    const std::string chunk(65536, 'A');
    for (int i = 0; i < 160; ++i) {   // 10 MiB without a newline
        feed(d, chunk);
        ASSERT_LE(d.bufferedBytes(), kMaxNmeaLineBytes);
    }
    EXPECT_EQ(d.counters().oversized, 1u);
    const std::vector<Fix> fixes = test::syntheticTrack(3, at("2026-03-20T08:00:00Z"), kNsPerSecond);
    std::vector<Fix> out = feed(d, std::string("\r\n") + track(fixes));
    const std::vector<Fix> rest = flush(d);
    out.insert(out.end(), rest.begin(), rest.end());
    EXPECT_EQ(out.size(), 3u) << "the feed goes on after the endless line";
    EXPECT_EQ(d.counters().malformed, 0u);
}

TEST(NmeaDecoder, RandomGarbageIsCountedAndTheFeedGoesOn) {
    std::mt19937 rng(7);
    std::string garbage(65536, '\0');
    for (char& c : garbage) c = char(rng() & 0xff);
    NmeaDecoder d;
    std::vector<Fix> out = feed(d, garbage);
    EXPECT_LE(d.bufferedBytes(), kMaxNmeaLineBytes);
    EXPECT_GT(d.counters().malformed + d.counters().badChecksum + d.counters().oversized, 0u);
    const std::vector<Fix> fixes = test::syntheticTrack(4, at("2026-03-20T08:00:00Z"), kNsPerSecond);
    const std::vector<Fix> good = feed(d, std::string("\n") + track(fixes));
    out.insert(out.end(), good.begin(), good.end());
    const std::vector<Fix> rest = flush(d);
    out.insert(out.end(), rest.begin(), rest.end());
    ASSERT_GE(out.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(out[out.size() - 4 + i].time, fixes[i].time);
}

TEST(NmeaDecoder, BytesBeforeTheDollarOnTheSameLineAreIgnored) {
    NmeaDecoder d;
    feed(d, "\x01\xb5\x62 a line without a dollar\r\n");   // one malformed
    feed(d, std::string("\xb5\x62\x01\x07 binary") + gga("123519"));
    ASSERT_EQ(flush(d).size(), 1u);
    EXPECT_EQ(d.counters().messagesOk, 1u);
    EXPECT_EQ(d.counters().malformed, 1u);
}

TEST(NmeaDecoder, AnySplitOfTheStreamGivesTheSameFixes) {
    const std::vector<Fix> fixes = test::syntheticTrack(20, at("2026-03-20T08:00:00Z"), kNsPerSecond / 5);
    const std::string stream = track(fixes);
    for (std::size_t chunk : {std::size_t(1), std::size_t(7), std::size_t(83), stream.size()}) {
        NmeaDecoder d;
        std::vector<Fix> out;
        for (std::size_t i = 0; i < stream.size(); i += chunk) {
            const std::vector<Fix> part = feed(d, std::string_view(stream).substr(i, chunk));
            out.insert(out.end(), part.begin(), part.end());
        }
        const std::vector<Fix> rest = flush(d);
        out.insert(out.end(), rest.begin(), rest.end());
        ASSERT_EQ(out.size(), fixes.size()) << "chunks of " << chunk;
        for (std::size_t i = 0; i < fixes.size(); ++i) EXPECT_EQ(out[i].time, fixes[i].time);
    }
}

TEST(NmeaDecoder, AcceptsCrLfLfAndCrLineEnds) {
    std::string g = gga("123519");
    g.resize(g.size() - 2);   // without "\r\n"
    for (const char* end : {"\r\n", "\n", "\r"}) {
        NmeaDecoder d;
        feed(d, g + end + g + end);
        EXPECT_EQ(d.counters().messagesOk, 2u) << "line end " << int(end[0]);
        EXPECT_EQ(d.counters().malformed, 0u);
    }
}

TEST(NmeaDecoder, VtgWithoutAnEpochJoinsNothing) {
    NmeaDecoder d;
    std::vector<Fix> out = feed(d, vtg(99.0) + gga("120000") + rmc("120000", "190326") + vtg(10.0) + vtg(98.0));
    const std::vector<Fix> rest = flush(d);
    out.insert(out.end(), rest.begin(), rest.end());
    ASSERT_EQ(out.size(), 1u);
    EXPECT_NEAR(*out[0].speedMps, 10.0 * kMpsPerKnot, 1e-6) << "the VTG before any epoch and the second VTG are not merged";
    EXPECT_EQ(d.counters().messagesOk, 5u);
}

TEST(NmeaDecoder, MissingSentenceHoldsTheFixUntilFlushOrTheNextEpoch) {
    const std::vector<Fix> fixes = test::syntheticTrack(4, at("2026-03-20T08:00:00Z"), kNsPerSecond);
    const NmeaWriter w;
    NmeaDecoder d;
    feed(d, w.epoch(fixes[0]) + w.epoch(fixes[1]));   // learns GGA + RMC + VTG
    EXPECT_TRUE(feed(d, w.gga(fixes[2]) + w.rmc(fixes[2])).empty()) << "its VTG is missing";
    const std::vector<Fix> flushed = flush(d);
    ASSERT_EQ(flushed.size(), 1u);
    EXPECT_EQ(flushed[0].time, fixes[2].time);
    const std::vector<Fix> next = feed(d, w.epoch(fixes[3]));
    ASSERT_EQ(next.size(), 1u) << "no second fix for epoch 2";
    EXPECT_EQ(next[0].time, fixes[3].time);
}

TEST(NmeaDecoder, LastLineOfADatagramNeedsNoNewline) {
    NmeaDecoder d;
    std::string g = gga("123519");
    g.resize(g.size() - 2);
    std::vector<Fix> out;
    d.feed(g, Clock::now(), out);
    EXPECT_EQ(d.counters().messagesOk, 0u);
    d.endOfRecord(Clock::now(), out);
    EXPECT_EQ(d.counters().messagesOk, 1u);
}

TEST(NmeaDecoder, OtherSentencesAreCountedAsUnknown) {
    NmeaDecoder d;
    feed(d, nmeaSentence("GPGSA,A,3,04,05,,09,12,,,24,,,,,2.5,1.3,2.1") + nmeaSentence("GPGSV,1,1,01,03,03,111,00"));
    EXPECT_EQ(d.counters().unknownType, 2u);
    EXPECT_EQ(d.counters().malformed + d.counters().badChecksum, 0u);
}

TEST(NmeaWriter, RoundTripThroughTheDecoderKeepsEveryValue) {
    // 50 fixes at 10 Hz across midnight: the dates come from RMC and roll over with it.
    const std::vector<Fix> fixes = test::syntheticTrack(50, at("2026-03-19T23:59:57.5Z"), kNsPerSecond / 10);
    NmeaDecoder d;
    std::vector<Fix> out = feed(d, track(fixes));
    const std::vector<Fix> rest = flush(d);
    out.insert(out.end(), rest.begin(), rest.end());
    ASSERT_EQ(out.size(), fixes.size());
    EXPECT_EQ(d.counters().badChecksum + d.counters().malformed, 0u);
    for (std::size_t i = 0; i < fixes.size(); ++i) {
        const Fix& a = fixes[i];
        const Fix& b = out[i];
        EXPECT_EQ(b.time, a.time) << i;
        EXPECT_NEAR(b.latDeg, a.latDeg, 2e-8) << i;          // 1e-6 arc minute = 1.7e-8 degree
        EXPECT_NEAR(b.lonDeg, a.lonDeg, 2e-8) << i;
        EXPECT_NEAR(*b.altitudeMsl, *a.altitudeMsl, 6e-4) << i;   // written to the millimetre
        EXPECT_NEAR(*b.heightEllipsoid, *a.heightEllipsoid, 1.1e-3) << i;   // alt + separation: two roundings
        EXPECT_NEAR(*b.speedMps, *a.speedMps, 2e-4) << i;    // 0.001 km/h = 2.8e-4 m/s, rounded: half of it
        EXPECT_NEAR(*b.courseDeg, *a.courseDeg, 5.1e-3) << i;   // 0.01 degree, rounded
        EXPECT_EQ(b.quality, 1);
        EXPECT_EQ(b.satellites, 9);
    }
}

TEST(NmeaWriter, SouthWestAndHeightOnlyFixesRoundTrip) {
    Fix f;
    f.time = at("2026-03-20T08:00:00.123Z");
    f.latDeg = -33.8583;
    f.lonDeg = -151.2125;
    f.heightEllipsoid = -12.5;   // below the ellipsoid, no MSL altitude known
    const std::string line = NmeaWriter("GN").gga(f);
    const NmeaSentence s = parseNmeaSentence(line);
    ASSERT_EQ(s.status, NmeaStatus::Ok) << s.error;
    EXPECT_EQ(s.talker, "GN");
    const auto& g = std::get<NmeaGga>(s.data);
    EXPECT_NEAR(*g.latDeg, -33.8583, 2e-8);
    EXPECT_NEAR(*g.lonDeg, -151.2125, 2e-8);
    EXPECT_NEAR(*g.altitudeMsl + *g.geoidSeparation, -12.5, 1e-9);
    EXPECT_EQ(*g.timeOfDay, (8 * 3600) * kNsPerSecond + 123'000'000);
}

}  // namespace
}  // namespace orbis::livefeed
