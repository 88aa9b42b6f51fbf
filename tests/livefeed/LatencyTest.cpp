// Socket-to-consumer latency of LiveSource. The test asserts only correctness (every fix, in
// order); the times are printed ("[latency] ...") and recorded as test properties, not asserted.
//
// How it is measured: a sender thread plays a synthetic track at a fixed rate and stamps each
// epoch with steady_clock just before send(). Sender and LiveSource are in this process, so one
// clock serves both. For each fix the consumer gets, its index follows from its time, and:
//   wire  = Fix::received (recv() returned)  - send stamp   (kernel + reader wake-up)
//   total = the instant drain() returned it  - send stamp   (adds decoding, queueing, waking
//                                                            the consumer)
// The consumer either waits on waitForFixes() (event-driven: the pipeline's own latency) or
// drains once per 60 Hz frame (what a viewer sees: adds up to a frame, ~8 ms on average).

#include "formats/livefeed/LiveSource.h"
#include "formats/livefeed/NmeaWriter.h"
#include "formats/livefeed/XmlFix.h"
#include "tests/livefeed/FeedServer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <thread>

namespace orbis::livefeed {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

const TimeNs kStart = *parseIso8601("2026-03-20T08:00:00Z");

struct Summary {
    double medianMs = 0, p95Ms = 0, maxMs = 0;
};

Summary summarize(std::vector<double> ms) {
    Summary s;
    if (ms.empty()) return s;
    std::sort(ms.begin(), ms.end());
    s.medianMs = ms[ms.size() / 2];
    s.p95Ms = ms[std::min(ms.size() - 1, ms.size() * 95 / 100)];
    s.maxMs = ms.back();
    return s;
}

struct LatencyRun {
    Transport transport = Transport::Tcp;
    FeedProtocol protocol = FeedProtocol::Nmea;
    int count = 200;
    std::chrono::microseconds period = 10ms;         // 100 Hz
    std::chrono::microseconds framePeriod = 0us;      // 0: event-driven consumer
};

void measure(const LatencyRun& run, const char* label) {
    const TimeNs step = std::chrono::duration_cast<std::chrono::nanoseconds>(run.period).count();
    const std::vector<Fix> track = test::syntheticTrack(run.count, kStart, step);
    std::vector<std::string> messages;
    const NmeaWriter writer;
    for (const Fix& f : track) messages.push_back(run.protocol == FeedProtocol::Nmea ? writer.epoch(f) : formatXmlFix(f) + "\n");

    LiveSourceOptions options;
    options.protocol = run.protocol;
    options.referenceTime = kStart;
    std::unique_ptr<test::TcpFeedServer> server;
    std::string url = "udp://127.0.0.1:0";
    if (run.transport == Transport::Tcp) {
        server = std::make_unique<test::TcpFeedServer>();
        ASSERT_TRUE(server->ok()) << server->error();
        url = server->url();
    }
    Result<std::unique_ptr<LiveSource>> opened = LiveSource::open(url, options);
    ASSERT_TRUE(opened.ok()) << opened.message();
    LiveSource& source = **opened;
    if (server) {
        ASSERT_TRUE(server->acceptClient());
    } else {
        ASSERT_TRUE(test::waitUntil([&] { return source.stats().localPort != 0; }));
    }
    std::unique_ptr<test::UdpSender> udp;
    if (!server) udp = std::make_unique<test::UdpSender>(source.stats().localPort);

    std::vector<std::atomic<std::int64_t>> sentNs(track.size());
    std::thread sender([&] {
        const auto t0 = Clock::now() + 20ms;
        for (std::size_t i = 0; i < messages.size(); ++i) {
            std::this_thread::sleep_until(t0 + i * run.period);
            sentNs[i] = Clock::now().time_since_epoch().count();
            if (server) server->send(messages[i]);
            else udp->send(messages[i]);
        }
    });

    std::vector<double> wire, total;
    std::vector<Fix> got;
    const auto deadline = Clock::now() + 10s + run.count * run.period;
    auto nextFrame = Clock::now();
    while (got.size() < track.size() && Clock::now() < deadline) {
        if (run.framePeriod.count() == 0) {
            source.waitForFixes(50ms);
        } else {
            nextFrame += run.framePeriod;
            std::this_thread::sleep_until(nextFrame);
        }
        std::vector<Fix> fixes = source.drain();
        const std::int64_t drained = Clock::now().time_since_epoch().count();
        for (Fix& f : fixes) {
            const std::size_t i = std::size_t((f.time - kStart) / step);
            if (i < sentNs.size()) {
                const std::int64_t sent = sentNs[i].load();
                wire.push_back(double(f.received.time_since_epoch().count() - sent) * 1e-6);
                total.push_back(double(drained - sent) * 1e-6);
            }
            got.push_back(std::move(f));
        }
    }
    sender.join();

    ASSERT_EQ(got.size(), track.size()) << source.stats().decoded.lastError;
    for (std::size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i].time, track[i].time) << "fix " << i;

    const Summary w = summarize(wire), t = summarize(total);
    std::printf("[latency] %-34s n=%zu  socket->Fix median %.3f ms p95 %.3f max %.3f | socket->drain median %.3f ms p95 %.3f max %.3f\n",
                label, got.size(), w.medianMs, w.p95Ms, w.maxMs, t.medianMs, t.p95Ms, t.maxMs);
    ::testing::Test::RecordProperty("socket_to_fix_median_us", int(w.medianMs * 1000));
    ::testing::Test::RecordProperty("socket_to_drain_median_us", int(t.medianMs * 1000));
}

TEST(LiveFeedLatency, NmeaOverTcpAt100HzEventDriven) {
    measure(LatencyRun{}, "NMEA/TCP 100 Hz, waitForFixes");
}

TEST(LiveFeedLatency, XmlOverUdpAt100HzEventDriven) {
    LatencyRun run;
    run.transport = Transport::Udp;
    run.protocol = FeedProtocol::Xml;
    measure(run, "XML/UDP 100 Hz, waitForFixes");
}

TEST(LiveFeedLatency, NmeaOverTcpAt100HzDrainedPerFrame) {
    LatencyRun run;
    run.framePeriod = std::chrono::microseconds(16667);   // a 60 Hz viewer
    measure(run, "NMEA/TCP 100 Hz, drained at 60 Hz");
}

}  // namespace
}  // namespace orbis::livefeed
