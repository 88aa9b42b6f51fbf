// The XML position message (XmlFix.h): both forms, errors, and the stream decoder's framing,
// resynchronisation and bounds. Also the protocol auto-detection (FixDecoder.h).

#include "formats/livefeed/NmeaWriter.h"
#include "formats/livefeed/XmlFix.h"

#include <gtest/gtest.h>

namespace orbis::livefeed {
namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kAttributeForm =
    R"(<position time="2026-03-20T08:00:00.5Z" lat="46.1" lon="7.2" alt="1500" heading="90" speed="55" vspeed="-1.2"/>)";
constexpr const char* kChildForm =
    "<position>\n  <time>2026-03-20T08:00:01Z</time>\n  <lat> 46.2 </lat>\n  <lon>7.3</lon>\n  <alt>1510</alt>\n"
    "  <course>91.5</course>\n</position>";

TimeNs at(const char* iso) { return *parseIso8601(iso); }

std::vector<Fix> feed(FixDecoder& d, std::string_view bytes) {
    std::vector<Fix> out;
    d.feed(bytes, Clock::now(), out);
    return out;
}

TEST(XmlFix, AttributeFormDecodes) {
    const Result<Fix> f = parseXmlFix(kAttributeForm);
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ(f->time, at("2026-03-20T08:00:00.5Z"));
    EXPECT_DOUBLE_EQ(f->latDeg, 46.1);
    EXPECT_DOUBLE_EQ(f->lonDeg, 7.2);
    EXPECT_DOUBLE_EQ(*f->heightEllipsoid, 1500.0);   // altRef defaults to the ellipsoid
    EXPECT_FALSE(f->altitudeMsl);
    EXPECT_DOUBLE_EQ(*f->headingDeg, 90.0);
    EXPECT_DOUBLE_EQ(*f->speedMps, 55.0);
    EXPECT_DOUBLE_EQ(*f->verticalSpeedMps, -1.2);
    EXPECT_FALSE(f->courseDeg);
    EXPECT_EQ(f->format, FixFormat::Xml);
}

TEST(XmlFix, ChildElementFormDecodes) {
    const Result<Fix> f = parseXmlFix(kChildForm);
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ(f->time, at("2026-03-20T08:00:01Z"));
    EXPECT_DOUBLE_EQ(f->latDeg, 46.2);   // surrounding spaces are allowed
    EXPECT_DOUBLE_EQ(*f->heightEllipsoid, 1510.0);
    EXPECT_DOUBLE_EQ(*f->courseDeg, 91.5);
}

TEST(XmlFix, AltitudeIsAboveMeanSeaLevelWhenAltRefSaysMsl) {
    const Result<Fix> f = parseXmlFix(R"(<position time="2026-03-20T08:00:00Z" lat="1" lon="2" alt="12.5" altRef="msl" pitch="3" roll="-4"/>)");
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_DOUBLE_EQ(*f->altitudeMsl, 12.5);
    EXPECT_FALSE(f->heightEllipsoid);
    EXPECT_DOUBLE_EQ(*f->pitchDeg, 3.0);
    EXPECT_DOUBLE_EQ(*f->rollDeg, -4.0);
}

TEST(XmlFix, UnknownAttributesAndElementsAreIgnored) {
    const Result<Fix> f = parseXmlFix(
        R"(<position id="HB-ABC" time="2026-03-20T08:00:00Z" lat="1" lon="2"><name>glider</name><extra><lat>9</lat></extra></position>)");
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_DOUBLE_EQ(f->latDeg, 1.0) << "only direct children are values";
}

TEST(Fix, DescribeGivesTimePositionAndTheKnownValues) {
    const Result<Fix> f = parseXmlFix(R"(<position time="2026-03-20T08:00:00.5Z" lat="-46.1" lon="7.2" speed="55"/>)");
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ(describe(*f), "2026-03-20T08:00:00.500Z 46.1000000S 7.2000000E speed=55.00");
}

TEST(XmlFix, BadValuesAreErrorsThatNameTheValue) {
    struct Case {
        const char* xml;
        const char* reason;
    };
    const Case cases[] = {
        {R"(<position lat="1" lon="2"/>)", "no time"},
        {R"(<position time="2026-03-20T08:00:00Z" lon="2"/>)", "no lat"},
        {R"(<position time="yesterday" lat="1" lon="2"/>)", "time:"},
        {R"(<position time="2026-03-20T08:00:00Z" lat="north" lon="2"/>)", "lat 'north' is not a number"},
        {R"(<position time="2026-03-20T08:00:00Z" lat="91" lon="2"/>)", "lat 91 is outside"},
        {R"(<position time="2026-03-20T08:00:00Z" lat="1" lon="-181"/>)", "lon -181 is outside"},
        {R"(<position time="2026-03-20T08:00:00Z" lat="1" lon="2" speed="nan"/>)", "speed 'nan' is not a number"},
        {R"(<position time="2026-03-20T08:00:00Z" lat="1" lon="2" alt="5" altRef="agl"/>)", "altRef 'agl'"},
        {R"(<position time="2026-03-20T08:00:00Z" lat="1" lon="2")", "XML position message"},
        {R"(<fix time="2026-03-20T08:00:00Z" lat="1" lon="2"/>)", "not <position>"},
        {R"(<position time="2026-03-20T08:00:00Z" lat="1" lon="2"><alt>1</altitude></position>)", "mismatched tag"},
    };
    for (const Case& c : cases) {
        const Result<Fix> f = parseXmlFix(c.xml);
        ASSERT_FALSE(f.ok()) << c.xml;
        EXPECT_NE(f.message().find(c.reason), std::string::npos) << c.xml << " -> " << f.message();
        EXPECT_NE(f.message().find("XML position message '<"), std::string::npos) << "quotes the message: " << f.message();
    }
}

TEST(XmlFix, FormatRoundTripsInBothForms) {
    Fix f;
    f.time = at("2026-03-20T08:00:00.123456789Z");
    f.latDeg = -33.123456789;
    f.lonDeg = 151.987654321;
    f.altitudeMsl = -3.25;
    f.headingDeg = 359.5;
    f.speedMps = 0.125;
    f.verticalSpeedMps = -2.5;
    for (bool children : {false, true}) {
        const Result<Fix> g = parseXmlFix(formatXmlFix(f, children));
        ASSERT_TRUE(g.ok()) << g.message();
        EXPECT_EQ(g->time, f.time);
        EXPECT_NEAR(g->latDeg, f.latDeg, 1e-9);
        EXPECT_NEAR(g->lonDeg, f.lonDeg, 1e-9);
        EXPECT_DOUBLE_EQ(*g->altitudeMsl, -3.25);
        EXPECT_FALSE(g->heightEllipsoid);
        EXPECT_DOUBLE_EQ(*g->headingDeg, 359.5);
        EXPECT_DOUBLE_EQ(*g->speedMps, 0.125);
        EXPECT_DOUBLE_EQ(*g->verticalSpeedMps, -2.5);
        EXPECT_FALSE(g->courseDeg);
    }
}

TEST(XmlFixDecoder, MalformedMessageIsCountedAndTheNextOneRead) {
    XmlFixDecoder d;
    const std::vector<Fix> out = feed(d, std::string(kAttributeForm) + "\n" +
                                             R"(<position time="2026-03-20T08:00:00Z" lat="1" lon="2" lat="3"/>)" "\n" + kChildForm + "\n");
    ASSERT_EQ(out.size(), 2u);
    EXPECT_DOUBLE_EQ(out[0].latDeg, 46.1);
    EXPECT_DOUBLE_EQ(out[1].latDeg, 46.2);
    EXPECT_EQ(d.counters().malformed, 1u);
    EXPECT_NE(d.counters().lastError.find("duplicate attribute"), std::string::npos) << d.counters().lastError;
    EXPECT_EQ(d.counters().messagesOk, 2u);
}

TEST(XmlFixDecoder, MessagesSplitAcrossReadsDecode) {
    const std::string stream = std::string(kAttributeForm) + kChildForm + "\r\n" + kAttributeForm;
    for (std::size_t chunk : {std::size_t(1), std::size_t(2), std::size_t(13), stream.size()}) {
        XmlFixDecoder d;
        std::vector<Fix> out;
        for (std::size_t i = 0; i < stream.size(); i += chunk) {
            const std::vector<Fix> part = feed(d, std::string_view(stream).substr(i, chunk));
            out.insert(out.end(), part.begin(), part.end());
        }
        ASSERT_EQ(out.size(), 3u) << "chunks of " << chunk;
        EXPECT_DOUBLE_EQ(out[1].latDeg, 46.2);
        EXPECT_EQ(d.counters().malformed, 0u);
    }
}

TEST(XmlFixDecoder, OversizedMessageIsDroppedWithoutGrowing) {
    XmlFixDecoder d;
    feed(d, R"(<position time="2026-03-20T08:00:00Z" lat=")");
    const std::string chunk(65536, '1');
    for (int i = 0; i < 64; ++i) {   // 4 MiB inside one attribute value
        feed(d, chunk);
        ASSERT_LE(d.bufferedBytes(), kMaxXmlMessageBytes);
    }
    const std::vector<Fix> out = feed(d, std::string("\" lon=\"2\"/>\n") + kAttributeForm);
    ASSERT_EQ(out.size(), 1u) << "the decoder resumes at the next <position";
    EXPECT_DOUBLE_EQ(out[0].latDeg, 46.1);
    EXPECT_EQ(d.counters().oversized, 1u);
    EXPECT_EQ(d.counters().malformed, 0u) << "the rest of the dropped message is skipped silently";
}

TEST(XmlFixDecoder, DeclarationsCommentsAndAWrappingElementAreSkipped) {
    XmlFixDecoder d;
    const std::vector<Fix> out = feed(d, std::string("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<feed source=\"sim\">\n") +
                                             "<!-- a comment with <position> and > inside -->\n" + kAttributeForm + "\n" +
                                             kChildForm + "\n</feed>\n");
    EXPECT_EQ(out.size(), 2u);
    EXPECT_EQ(d.counters().malformed, 0u) << d.counters().lastError;
}

TEST(XmlFixDecoder, QuotedGreaterThanDoesNotEndTheStartTag) {
    XmlFixDecoder d;
    const std::vector<Fix> out = feed(d, R"(<position note="a>b/>c" time="2026-03-20T08:00:00Z" lat="1" lon="2"/>)");
    ASSERT_EQ(out.size(), 1u) << d.counters().lastError;
    EXPECT_DOUBLE_EQ(out[0].lonDeg, 2.0);
}

TEST(XmlFixDecoder, CutOffMessagesResyncAtTheNextPosition) {
    XmlFixDecoder d;
    const std::vector<Fix> out = feed(d, std::string(R"(<position time="2026-03-20T08:00:00Z" lat="1)") + "\n" + kAttributeForm +
                                             "<position><time>2026-03-20T08:00:00Z</time><lat>5" + kChildForm);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_DOUBLE_EQ(out[0].latDeg, 46.1);
    EXPECT_DOUBLE_EQ(out[1].latDeg, 46.2);
    EXPECT_EQ(d.counters().malformed, 2u);
}

TEST(XmlFixDecoder, TextOutsideMessagesIsCountedOncePerRun) {
    XmlFixDecoder d;
    const std::vector<Fix> out = feed(d, std::string("hello world ") + kAttributeForm + " junk junk " + kAttributeForm);
    EXPECT_EQ(out.size(), 2u);
    EXPECT_EQ(d.counters().malformed, 2u);
}

TEST(XmlFixDecoder, UnfinishedMessageAtTheEndOfADatagramIsDropped) {
    XmlFixDecoder d;
    std::vector<Fix> out = feed(d, std::string(kAttributeForm) + R"(<position time="2026-03-20T08:00:00Z")");
    d.endOfRecord(Clock::now(), out);
    const std::vector<Fix> next = feed(d, R"( lat="1" lon="2"/>)" + std::string(kAttributeForm));
    EXPECT_EQ(out.size(), 1u);
    EXPECT_EQ(next.size(), 1u) << "the next datagram starts afresh";
    EXPECT_EQ(d.counters().malformed, 2u) << "the cut message, then the next datagram's leading text";
}

TEST(FixDecoder, AutoDetectsNmeaOrXmlPerConnection) {
    DecoderOptions options;
    options.referenceTime = at("2026-03-20T00:00:00Z");
    const std::unique_ptr<FixDecoder> d = makeDecoder(FeedProtocol::Auto, options);
    EXPECT_EQ(d->protocol(), FeedProtocol::Auto);
    std::vector<Fix> out;
    d->feed("\r\n  " + nmeaSentence("GPGGA,080000,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"), Clock::now(), out);
    EXPECT_EQ(d->protocol(), FeedProtocol::Nmea);
    d->flush(Clock::now(), out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].format, FixFormat::Nmea);

    d->resetInput();   // a new connection may speak the other protocol
    d->feed(std::string("garbage ") + kAttributeForm, Clock::now(), out);
    EXPECT_EQ(d->protocol(), FeedProtocol::Xml);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[1].format, FixFormat::Xml);
    EXPECT_EQ(d->counters().malformed, 1u) << "the bytes before '<'";
    EXPECT_EQ(d->counters().fixes, 2u);
}

}  // namespace
}  // namespace orbis::livefeed
