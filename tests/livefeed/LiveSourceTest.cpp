// LiveSource over real sockets on 127.0.0.1: a test server plays a synthetic track (written with
// NmeaWriter or formatXmlFix) and the source must deliver every fix, in order, through server
// restarts, refused connections, garbage and endless lines. Every wait has a deadline (5 s);
// none of these tests sleeps for a fixed time to let something happen.

#include "formats/livefeed/LiveSource.h"
#include "formats/livefeed/Nmea.h"
#include "formats/livefeed/NmeaWriter.h"
#include "formats/livefeed/XmlFix.h"
#include "tests/livefeed/FeedServer.h"

#include <gtest/gtest.h>

#include <netdb.h>

#include <ctime>
#include <random>

namespace orbis::livefeed {
namespace {

using namespace std::chrono_literals;
using test::TcpFeedServer;
using test::waitUntil;
using Clock = std::chrono::steady_clock;

const TimeNs kStart = *parseIso8601("2026-03-20T08:00:00Z");

/// Collects fixes from `source` until `count` have come or 5 s pass.
std::vector<Fix> collect(LiveSource& source, std::size_t count, std::vector<Fix> into = {}) {
    const auto deadline = Clock::now() + 5s;
    while (into.size() < count && Clock::now() < deadline) {
        source.waitForFixes(50ms);
        for (Fix& f : source.drain()) into.push_back(std::move(f));
    }
    return into;
}

std::unique_ptr<LiveSource> openOrFail(const std::string& url, LiveSourceOptions options = {}) {
    options.referenceTime = kStart;
    Result<std::unique_ptr<LiveSource>> s = LiveSource::open(url, options);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.message());
    return s.ok() ? std::move(*s) : nullptr;
}

void expectSameFixes(const std::vector<Fix>& got, const std::vector<Fix>& sent, std::size_t firstSent = 0) {
    ASSERT_LE(firstSent + got.size(), sent.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        const Fix& a = sent[firstSent + i];
        const Fix& b = got[i];
        EXPECT_EQ(b.time, a.time) << "fix " << i;
        EXPECT_NEAR(b.latDeg, a.latDeg, 2e-8) << "fix " << i;   // NMEA: 1e-6 arc minute
        EXPECT_NEAR(b.lonDeg, a.lonDeg, 2e-8) << "fix " << i;
        EXPECT_NEAR(*b.heightEllipsoid, *a.heightEllipsoid, 1.1e-3) << "fix " << i;
        EXPECT_NEAR(*b.speedMps, *a.speedMps, 2e-4) << "fix " << i;
        EXPECT_NEAR(*b.courseDeg, *a.courseDeg, 5.1e-3) << "fix " << i;
        if (i > 0) {
            EXPECT_GT(b.sequence, got[i - 1].sequence);
        }
    }
}

std::string nmeaTrack(const std::vector<Fix>& fixes, std::size_t from, std::size_t to) {
    const NmeaWriter writer("GN");
    std::string s;
    for (std::size_t i = from; i < to; ++i) s += writer.epoch(fixes[i]);
    return s;
}

TEST(FeedAddress, ParsesTcpUdpAndIpv6) {
    const Result<FeedAddress> tcp = parseFeedAddress("tcp://gps.local:10110");
    ASSERT_TRUE(tcp.ok()) << tcp.message();
    EXPECT_EQ(tcp->transport, Transport::Tcp);
    EXPECT_EQ(tcp->host, "gps.local");
    EXPECT_EQ(tcp->port, 10110);
    const Result<FeedAddress> v6 = parseFeedAddress("tcp://[::1]:5000/");
    ASSERT_TRUE(v6.ok()) << v6.message();
    EXPECT_EQ(v6->host, "::1");
    EXPECT_EQ(v6->hostPort(), "[::1]:5000");
    const Result<FeedAddress> udp = parseFeedAddress("udp://:0");
    ASSERT_TRUE(udp.ok()) << udp.message();
    EXPECT_EQ(udp->transport, Transport::Udp);
    EXPECT_EQ(udp->host, "0.0.0.0");
    EXPECT_EQ(udp->port, 0);
}

TEST(FeedAddress, BadAddressesAreClearErrors) {
    struct Case {
        const char* url;
        const char* reason;
    };
    const Case cases[] = {
        {"tcp://host:99999", "port 99999 is out of range"},
        {"tcp://host:0", "port 0 is out of range 1..65535"},
        {"tcp://host:12a", "is not a number"},
        {"tcp://host", "no port"},
        {"tcp://:5000", "no host"},
        {"http://host:80", "expected tcp://host:port or udp://host:port"},
        {"tcp://::1:5000", "must be in brackets"},
        {"tcp://[::1:5000", "without ']'"},
        {"udp://host:-1", "port -1 is out of range 0..65535"},
    };
    for (const Case& c : cases) {
        const Result<FeedAddress> a = parseFeedAddress(c.url);
        ASSERT_FALSE(a.ok()) << c.url;
        EXPECT_NE(a.message().find(c.reason), std::string::npos) << c.url << " -> " << a.message();
        EXPECT_NE(a.message().find(std::string("live feed '") + c.url + "'"), std::string::npos) << a.message();
    }
    const Result<std::unique_ptr<LiveSource>> s = LiveSource::open("tcp://host:99999");
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.message().find("port 99999 is out of range"), std::string::npos) << s.message();
}

TEST(LiveSource, TcpDeliversARecordedTrackInOrder) {
    TcpFeedServer server;
    ASSERT_TRUE(server.ok()) << server.error();
    auto source = openOrFail(server.url());
    ASSERT_TRUE(source);
    ASSERT_TRUE(server.acceptClient());
    const std::vector<Fix> track = test::syntheticTrack(50, kStart, kNsPerSecond / 10);
    ASSERT_TRUE(server.send(nmeaTrack(track, 0, track.size())));
    const std::vector<Fix> got = collect(*source, track.size());
    ASSERT_EQ(got.size(), track.size()) << source->stats().decoded.lastError;
    expectSameFixes(got, track);
    const LiveStats stats = source->stats();
    EXPECT_TRUE(stats.connected);
    EXPECT_EQ(stats.protocol, FeedProtocol::Nmea);
    EXPECT_EQ(stats.decoded.messagesOk, 150u);
    EXPECT_EQ(stats.decoded.badChecksum + stats.decoded.malformed, 0u);
    EXPECT_EQ(stats.reconnects, 0u);
    ASSERT_TRUE(source->latest());
    EXPECT_EQ(source->latest()->time, track.back().time);
}

TEST(LiveSource, UdpDatagramsWithSeveralLinesAndWithoutNewline) {
    auto source = openOrFail("udp://127.0.0.1:0");
    ASSERT_TRUE(source);
    ASSERT_TRUE(waitUntil([&] { return source->stats().localPort != 0; })) << source->stats().lastError;
    test::UdpSender sender(source->stats().localPort);
    const std::vector<Fix> track = test::syntheticTrack(30, kStart, kNsPerSecond / 10);
    for (std::size_t i = 0; i < track.size(); i += 3) {   // three epochs (nine lines) per datagram
        std::string datagram = nmeaTrack(track, i, i + 3);
        if (i == 9) datagram.resize(datagram.size() - 2);   // the last line without CR LF
        ASSERT_TRUE(sender.send(datagram));
    }
    const std::vector<Fix> got = collect(*source, track.size());
    ASSERT_EQ(got.size(), track.size()) << source->stats().decoded.lastError;
    expectSameFixes(got, track);
    EXPECT_EQ(source->stats().decoded.malformed, 0u);
}

TEST(LiveSource, XmlOverTcpIsDetectedAndDecoded) {
    TcpFeedServer server;
    ASSERT_TRUE(server.ok()) << server.error();
    auto source = openOrFail(server.url());
    ASSERT_TRUE(source);
    ASSERT_TRUE(server.acceptClient());
    const std::vector<Fix> track = test::syntheticTrack(20, kStart, kNsPerSecond / 10);
    std::string stream = "<?xml version=\"1.0\"?>\n<feed>\n";
    for (std::size_t i = 0; i < track.size(); ++i) stream += formatXmlFix(track[i], i % 2 == 1) + "\n";
    ASSERT_TRUE(server.send(stream));
    const std::vector<Fix> got = collect(*source, track.size());
    ASSERT_EQ(got.size(), track.size()) << source->stats().decoded.lastError;
    for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].time, track[i].time);
        EXPECT_NEAR(got[i].latDeg, track[i].latDeg, 1e-9);
        EXPECT_EQ(got[i].format, FixFormat::Xml);
    }
    EXPECT_EQ(source->stats().protocol, FeedProtocol::Xml);
}

TEST(LiveSource, ReconnectsWhenTheServerRestartsOnTheSamePort) {
    const std::vector<Fix> track = test::syntheticTrack(50, kStart, kNsPerSecond / 10);
    auto server = std::make_unique<TcpFeedServer>();
    ASSERT_TRUE(server->ok()) << server->error();
    const std::uint16_t port = server->port();
    auto source = openOrFail(server->url());
    ASSERT_TRUE(source);
    ASSERT_TRUE(server->acceptClient());
    ASSERT_TRUE(server->send(nmeaTrack(track, 0, 20)));
    std::vector<Fix> got = collect(*source, 20);
    ASSERT_EQ(got.size(), 20u);

    server->close();   // the server goes away ...
    ASSERT_TRUE(waitUntil([&] { return !source->stats().connected; }));
    server = std::make_unique<TcpFeedServer>(port);   // ... and comes back on the same port
    ASSERT_TRUE(server->ok()) << server->error();
    ASSERT_TRUE(server->acceptClient()) << source->stats().lastError;
    ASSERT_TRUE(server->send(nmeaTrack(track, 20, track.size())));
    got = collect(*source, track.size(), std::move(got));
    ASSERT_EQ(got.size(), track.size());
    expectSameFixes(got, track);
    const LiveStats stats = source->stats();
    EXPECT_GE(stats.reconnects, 1u);
    EXPECT_GE(stats.disconnects, 1u);
    EXPECT_TRUE(stats.connected);
    EXPECT_NE(stats.lastError.find("127.0.0.1:" + std::to_string(port)), std::string::npos) << stats.lastError;
}

TEST(LiveSource, ConnectionRefusedAtFirstThenTheServerAppears) {
    TcpFeedServer server(0, /*listenNow=*/false);   // bound, not listening: connects are refused
    ASSERT_TRUE(server.ok()) << server.error();
    auto source = openOrFail(server.url());
    ASSERT_TRUE(source);
    ASSERT_TRUE(waitUntil([&] { return source->stats().connectAttempts >= 2; }));
    LiveStats stats = source->stats();
    EXPECT_FALSE(stats.connected);
    EXPECT_NE(stats.lastError.find("refused"), std::string::npos) << stats.lastError;
    EXPECT_NE(stats.lastError.find(server.url()), std::string::npos) << "names the feed: " << stats.lastError;

    ASSERT_TRUE(server.listen());
    ASSERT_TRUE(server.acceptClient());
    const std::vector<Fix> track = test::syntheticTrack(10, kStart, kNsPerSecond / 10);
    ASSERT_TRUE(server.send(nmeaTrack(track, 0, track.size())));
    const std::vector<Fix> got = collect(*source, track.size());
    ASSERT_EQ(got.size(), track.size());
    expectSameFixes(got, track);
    EXPECT_EQ(source->stats().connections, 1u);
}

TEST(LiveSource, ResolvesHostNames) {
    // A bare system (a minbase chroot) may have no /etc/hosts: nothing to resolve against.
    addrinfo hints{};
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (getaddrinfo("localhost", nullptr, &hints, &found) != 0) GTEST_SKIP() << "this system does not resolve 'localhost'";
    freeaddrinfo(found);
    TcpFeedServer server;
    ASSERT_TRUE(server.ok()) << server.error();
    // "localhost" may resolve to ::1 first, where nothing listens: the next address is tried.
    auto source = openOrFail("tcp://localhost:" + std::to_string(server.port()));
    ASSERT_TRUE(source);
    ASSERT_TRUE(server.acceptClient()) << source->stats().lastError;
    EXPECT_TRUE(waitUntil([&] { return source->stats().connected; }));
}

TEST(LiveSource, StopReturnsQuicklyWhileTheServerIsSilent) {
    TcpFeedServer server;
    ASSERT_TRUE(server.ok()) << server.error();
    auto source = openOrFail(server.url());
    ASSERT_TRUE(source);
    ASSERT_TRUE(server.acceptClient());
    ASSERT_TRUE(waitUntil([&] { return source->stats().connected; }));
    const auto t0 = Clock::now();
    source->stop();
    // ~0 ms expected (the eventfd wakes poll()); 1 s leaves room for a loaded machine.
    EXPECT_LT(Clock::now() - t0, 1s);
    EXPECT_FALSE(source->stats().connected);
    source->stop();   // idempotent
}

TEST(LiveSource, StopReturnsQuicklyWhileWaitingToReconnect) {
    TcpFeedServer server(0, /*listenNow=*/false);
    ASSERT_TRUE(server.ok()) << server.error();
    LiveSourceOptions options;
    options.reconnectMin = 30s;   // the thread sleeps long after the first refusal
    options.reconnectMax = 30s;
    auto source = openOrFail(server.url(), options);
    ASSERT_TRUE(source);
    ASSERT_TRUE(waitUntil([&] { return source->stats().connectAttempts >= 1 && !source->stats().lastError.empty(); }));
    const auto t0 = Clock::now();
    source.reset();   // the destructor stops
    EXPECT_LT(Clock::now() - t0, 1s);
}

TEST(LiveSource, StopReturnsQuicklyWhileConnecting) {
    // 192.0.2.1 (TEST-NET-1, RFC 5737) is never routed: the connect hangs until its timeout,
    // or fails at once where there is no route; either way stop() must not wait for it.
    LiveSourceOptions options;
    options.connectTimeout = 30s;
    auto source = openOrFail("tcp://192.0.2.1:10110", options);
    ASSERT_TRUE(source);
    ASSERT_TRUE(waitUntil([&] { return source->stats().connectAttempts >= 1; }));
    const auto t0 = Clock::now();
    source->stop();
    EXPECT_LT(Clock::now() - t0, 1s);
}

TEST(LiveSource, DoesNotSpinWhileTheServerIsDown) {
    TcpFeedServer server(0, /*listenNow=*/false);
    ASSERT_TRUE(server.ok()) << server.error();
    LiveSourceOptions options;
    options.reconnectMin = 20ms;
    options.reconnectMax = 80ms;
    auto source = openOrFail(server.url(), options);
    ASSERT_TRUE(source);
    timespec c0{}, c1{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
    const auto t0 = Clock::now();
    ASSERT_TRUE(waitUntil([&] { return source->stats().connectAttempts >= 8; }));
    // Backoff 20, 40, 80, 80, ... ms: eight attempts take at least 20+40+80*5 = 460 ms.
    EXPECT_GE(Clock::now() - t0, 400ms);
    source->stop();
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c1);
    const double cpuS = double(c1.tv_sec - c0.tv_sec) + 1e-9 * double(c1.tv_nsec - c0.tv_nsec);
    EXPECT_LT(cpuS, 0.25) << "CPU seconds used while waiting (this thread polls every 2 ms too)";
}

TEST(LiveSource, EndlessLineDoesNotGrowMemory) {
    TcpFeedServer server;
    ASSERT_TRUE(server.ok()) << server.error();
    LiveSourceOptions options;
    options.protocol = FeedProtocol::Nmea;
    auto source = openOrFail(server.url(), options);
    ASSERT_TRUE(source);
    ASSERT_TRUE(server.acceptClient());
    const std::string chunk(65536, 'A');
    for (int i = 0; i < 64; ++i) ASSERT_TRUE(server.send(chunk));   // 4 MiB without a newline
    const std::vector<Fix> track = test::syntheticTrack(5, kStart, kNsPerSecond / 10);
    ASSERT_TRUE(server.send(std::string("\r\n") + nmeaTrack(track, 0, track.size())));
    const std::vector<Fix> got = collect(*source, track.size());
    ASSERT_EQ(got.size(), track.size());
    const LiveStats stats = source->stats();
    EXPECT_EQ(stats.decoded.oversized, 1u);
    EXPECT_LE(stats.maxBufferedBytes, kMaxNmeaLineBytes);
    EXPECT_GE(stats.decoded.bytes, 64u * 65536u);
}

TEST(LiveSource, EndlessXmlMessageDoesNotGrowMemory) {
    TcpFeedServer server;
    ASSERT_TRUE(server.ok()) << server.error();
    auto source = openOrFail(server.url());
    ASSERT_TRUE(source);
    ASSERT_TRUE(server.acceptClient());
    ASSERT_TRUE(server.send("<position><lat>"));
    const std::string chunk(65536, '7');
    for (int i = 0; i < 64; ++i) ASSERT_TRUE(server.send(chunk));
    const std::vector<Fix> track = test::syntheticTrack(3, kStart, kNsPerSecond / 10);
    std::string tail = "</lat></position>\n";
    for (const Fix& f : track) tail += formatXmlFix(f);
    ASSERT_TRUE(server.send(tail));
    const std::vector<Fix> got = collect(*source, track.size());
    ASSERT_EQ(got.size(), track.size());
    EXPECT_EQ(source->stats().decoded.oversized, 1u);
    EXPECT_LE(source->stats().maxBufferedBytes, kMaxXmlMessageBytes);
}

TEST(LiveSource, GarbageDoesNotStopTheFeed) {
    TcpFeedServer server;
    ASSERT_TRUE(server.ok()) << server.error();
    LiveSourceOptions options;
    options.protocol = FeedProtocol::Nmea;   // random bytes may hold a '<' before any '$'
    auto source = openOrFail(server.url(), options);
    ASSERT_TRUE(source);
    ASSERT_TRUE(server.acceptClient());
    std::mt19937 rng(11);
    std::string garbage(200000, '\0');
    for (char& c : garbage) c = char(rng() & 0xff);
    ASSERT_TRUE(server.send(garbage));
    const std::vector<Fix> track = test::syntheticTrack(10, kStart, kNsPerSecond / 10);
    ASSERT_TRUE(server.send(std::string("\n") + nmeaTrack(track, 0, track.size())));
    std::vector<Fix> got = collect(*source, track.size());
    ASSERT_EQ(got.size(), track.size());
    expectSameFixes(got, track);
    const LiveStats stats = source->stats();
    EXPECT_GT(stats.decoded.malformed + stats.decoded.badChecksum, 0u);
    EXPECT_LE(stats.maxBufferedBytes, kMaxNmeaLineBytes);
    EXPECT_TRUE(stats.connected);
}

TEST(LiveSource, SlowConsumerLosesTheOldestFixesAndTheyAreCounted) {
    TcpFeedServer server;
    ASSERT_TRUE(server.ok()) << server.error();
    LiveSourceOptions options;
    options.queueCapacity = 10;
    auto source = openOrFail(server.url(), options);
    ASSERT_TRUE(source);
    ASSERT_TRUE(server.acceptClient());
    const std::vector<Fix> track = test::syntheticTrack(50, kStart, kNsPerSecond / 10);
    ASSERT_TRUE(server.send(nmeaTrack(track, 0, track.size())));
    ASSERT_TRUE(waitUntil([&] { return source->stats().fixesReceived == track.size(); })) << source->stats().fixesReceived;
    const std::vector<Fix> got = source->drain();
    ASSERT_EQ(got.size(), 10u);
    EXPECT_EQ(source->stats().dropped, 40u);
    for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].sequence, 41u + i);
        EXPECT_EQ(got[i].time, track[40 + i].time);
    }
    EXPECT_TRUE(source->drain().empty());
    EXPECT_EQ(source->latest()->time, track.back().time);
}

}  // namespace
}  // namespace orbis::livefeed
