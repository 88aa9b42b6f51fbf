// Live FMV sources (layers/fmv/LiveVideo.h) on real streams over loopback: the synthetic flight
// sent in real time by the project's own writer through FFmpeg's udp:// and tcp:// protocols
// (tools/gen/FmvFixture.h), received, decoded and matched with its KLV poses; a lossy relay;
// a sender that stops and comes back; four feeds at once; a recording played back as a file.
// Every sender and relay stops by itself; every wait is bounded.
#include "layers/fmv/LiveVideo.h"
#include "layers/fmv/SyntheticFlight.h"
#include "layers/fmv/VideoFile.h"
#include "tools/gen/FmvFixture.h"
#include "tools/net/UdpRelay.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <future>
#include <map>
#include <thread>

namespace orbis::fmv {
namespace {

using namespace std::chrono_literals;

/// The flight sent to `url` on another thread.
struct Sender {
    std::atomic<bool> stop{false};
    std::future<Result<int>> done;
    Sender(const std::string& url, FmvStreamOptions o) {
        done = std::async(std::launch::async, [this, url, o] { return streamFmvFixture(url, o, stop); });
    }
    ~Sender() {
        stop = true;
        if (done.valid()) done.wait();
    }
    int finish() {
        auto r = done.get();
        EXPECT_TRUE(r) << r.message();
        return r ? *r : 0;
    }
};

/// What the main thread saw, polling due() every 5 ms.
struct Seen {
    std::map<uint64_t, LiveFrame> frames;   // by serial
};

/// Polls `live` until `until` says stop or `limit` passes.
void watch(LiveVideo& live, Seen& seen, const std::function<bool()>& until, std::chrono::milliseconds limit) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end && !until()) {
        if (auto f = live.due(wallClockSeconds())) seen.frames[f->frame->index] = *f;
        std::this_thread::sleep_for(5ms);
    }
}

/// Polls `live` while `sender` sends its `frames` (checked), then half a second more for the
/// last ones.
void watchUntilSent(LiveVideo& live, Seen& seen, Sender& sender, int frames, std::chrono::milliseconds limit) {
    watch(live, seen, [&] { return sender.done.wait_for(0s) == std::future_status::ready; }, limit);
    EXPECT_EQ(sender.finish(), frames);
    watch(live, seen, [&] { return false; }, 500ms);
}

FmvStreamOptions flight(int frames) {
    FmvStreamOptions o;
    o.frames = frames;
    o.fps = 10;
    o.width = 160;
    o.height = 120;
    return o;
}

/// Each frame shown carries the pose of its own time: frame n of the flight (n read from the
/// picture) has the packet of n / fps.
void expectPosesMatchFrames(const Seen& seen, int fps) {
    ASSERT_FALSE(seen.frames.empty());
    for (const auto& [serial, f] : seen.frames) {
        ASSERT_TRUE(f.pose) << "frame " << serial;
        const int n = fixtureFrameNumber(f.frame->rgba, f.frame->width, f.frame->height);
        const SensorPose want = SyntheticFlight::pose(double(n) / fps);
        EXPECT_NEAR(f.pose->latDeg, want.latDeg, 1e-6) << "frame " << n;
        EXPECT_NEAR(f.pose->lonDeg, want.lonDeg, 1e-6) << "frame " << n;
        EXPECT_NEAR(f.pose->platformHeadingDeg, want.platformHeadingDeg, 0.01) << "frame " << n;
        EXPECT_NEAR(f.pose->sensorAzimuthDeg, want.sensorAzimuthDeg, 0.01) << "frame " << n;
    }
}

/// Every frame of a flight of `frames` at 10 fps arrived, none lost, each with a pose, at least
/// `shownAtLeast` of them shown, each with the pose of its own time.
void expectWholeFlight(const LiveStats& s, const Seen& seen, uint64_t frames, size_t shownAtLeast) {
    EXPECT_EQ(s.framesDecoded, frames) << s.lastError;
    EXPECT_EQ(s.framesLost, 0u);
    EXPECT_GE(s.posesReceived, frames);
    EXPECT_GE(seen.frames.size(), shownAtLeast);
    expectPosesMatchFrames(seen, 10);
}

std::string udpUrl(int port) { return "udp://127.0.0.1:" + std::to_string(port); }

class LiveVideoParsing : public testing::TestWithParam<bool> {};
INSTANTIATE_TEST_SUITE_P(LiveVideo, LiveVideoParsing, testing::Values(false, true),
                         [](const auto& info) { return info.param ? "WholeFrames" : "Parsed"; });

TEST_P(LiveVideoParsing, ReceivesUdpFramesWithThePoseOfTheirTime) {
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    LiveOptions options;
    options.jitterSeconds = 0.05;
    options.wholeFrames = GetParam();
    auto live = LiveVideo::open(udpUrl(port), options);
    ASSERT_TRUE(live) << live.message();
    EXPECT_EQ((*live)->stats().state, LiveState::Connecting);
    std::this_thread::sleep_for(200ms);   // the receiver's socket is bound
    FmvStreamOptions o = flight(30);
    o.stampWallClock = true;
    Sender sender(udpUrl(port), o);
    Seen seen;
    watchUntilSent(**live, seen, sender, 30, 10s);
    const LiveStats s = (*live)->stats();
    EXPECT_EQ(s.state, LiveState::Live) << s.lastError;
    EXPECT_EQ(s.width, 160);
    EXPECT_EQ(s.height, 120);
    // With FFmpeg's parser the last frame waits for a next one that never comes.
    EXPECT_EQ(s.framesDecoded, GetParam() ? 30u : 29u);
    EXPECT_EQ(s.framesLost, 0u);
    EXPECT_EQ(s.corruptPackets, 0u);
    EXPECT_EQ(s.klvRejected, 0u);
    EXPECT_GE(s.posesReceived, 29u);
    EXPECT_GT(s.bytes, 10000u);
    // The frames that came in a burst while the stream was probed are skipped to the newest;
    // from there on each is shown (a 5 ms poll, a 50 ms jitter buffer; fewer on a loaded machine).
    EXPECT_GE(seen.frames.size(), 10u);
    expectPosesMatchFrames(seen, 10);
    ASSERT_TRUE(s.latencySeconds);
    std::printf("[latency] %s: last frame due %.1f ms after it was sent\n", GetParam() ? "whole frames" : "parsed",
                *s.latencySeconds * 1e3);
    EXPECT_GT(*s.latencySeconds, 0.0);
    EXPECT_LT(*s.latencySeconds, 1.5);
}

TEST(LiveVideo, ReceivesTcpWithAsynchronousKlv) {
    const int port = net::freeUdpPort();   // TCP and UDP ports are separate; a free number will do
    ASSERT_GT(port, 0);
    FmvStreamOptions o = flight(25);
    o.async = true;
    Sender sender("tcp://127.0.0.1:" + std::to_string(port) + "?listen=1&listen_timeout=8000", o);
    std::this_thread::sleep_for(200ms);
    auto live = LiveVideo::open("tcp://127.0.0.1:" + std::to_string(port), {});
    ASSERT_TRUE(live) << live.message();
    Seen seen;
    watchUntilSent(**live, seen, sender, 25, 10s);
    const LiveStats s = (*live)->stats();
    EXPECT_GE(s.framesDecoded, 24u);
    EXPECT_GE(s.posesReceived, 24u);
    EXPECT_GE(seen.frames.size(), 8u);
    expectPosesMatchFrames(seen, 10);
}

// SRT (libsrt through FFmpeg), in either role: the sender listening and the receiver calling it,
// or the receiver listening for a sender. The receiver's wait for a caller is bounded like any
// other (the layer closes at once).
class LiveVideoSrt : public testing::TestWithParam<bool> {};
INSTANTIATE_TEST_SUITE_P(LiveVideo, LiveVideoSrt, testing::Values(false, true),
                         [](const auto& info) { return info.param ? "ReceiverListens" : "SenderListens"; });

TEST_P(LiveVideoSrt, ReceivesTheFlightWithItsPoses) {
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    const std::string at = "srt://127.0.0.1:" + std::to_string(port);
    const bool receiverListens = GetParam();
    LiveOptions options;
    options.wholeFrames = true;
    std::unique_ptr<Sender> sender;
    if (!receiverListens) {
        sender = std::make_unique<Sender>(at + "?mode=listener", flight(25));
        std::this_thread::sleep_for(200ms);
    }
    auto live = LiveVideo::open(at + (receiverListens ? "?mode=listener" : "?mode=caller"), options);
    ASSERT_TRUE(live) << live.message();
    if (receiverListens) {
        std::this_thread::sleep_for(300ms);
        EXPECT_EQ((*live)->stats().state, LiveState::Connecting);
        sender = std::make_unique<Sender>(at + "?mode=caller", flight(25));
    }
    Seen seen;
    watchUntilSent(**live, seen, *sender, 25, 10s);
    expectWholeFlight((*live)->stats(), seen, 25, 8);
}

TEST(LiveVideo, SaysNoSignalWhenTheSenderStopsAndResumesWhenItReturns) {
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    LiveOptions options;
    options.noSignalSeconds = 1.0;
    options.retrySeconds = 0.2;
    options.wholeFrames = true;
    auto live = LiveVideo::open(udpUrl(port), options);
    ASSERT_TRUE(live) << live.message();
    std::this_thread::sleep_for(200ms);
    Seen seen;
    {
        Sender first(udpUrl(port), flight(12));
        watch(**live, seen, [&] { return first.done.wait_for(0s) == std::future_status::ready; }, 10s);
        EXPECT_EQ(first.finish(), 12);
    }
    const size_t before = seen.frames.size();
    EXPECT_GE(before, 5u);
    watch(**live, seen, [&] { return (*live)->stats().state == LiveState::NoSignal; }, 5s);
    LiveStats s = (*live)->stats();
    ASSERT_EQ(s.state, LiveState::NoSignal);
    EXPECT_NE(s.lastError.find("no data"), std::string::npos) << s.lastError;
    // The last frame stays what due() gives while there is no signal.
    auto held = (*live)->due(wallClockSeconds());
    ASSERT_TRUE(held);
    EXPECT_EQ(held->frame->index, seen.frames.rbegin()->first);
    EXPECT_EQ(fixtureFrameNumber(held->frame->rgba, held->frame->width, held->frame->height), 11) << "the sender's last frame";

    Sender second(udpUrl(port), flight(15));   // a new sender: its clock starts again
    watchUntilSent(**live, seen, second, 15, 10s);
    s = (*live)->stats();
    EXPECT_EQ(s.state, LiveState::Live);
    EXPECT_GE(s.reconnects, 1u);
    EXPECT_GE(seen.frames.size(), before + 3);
    // The frames after the return are placed by the new sender's packets.
    Seen after;
    for (const auto& [serial, f] : seen.frames)
        if (serial > held->frame->index) after.frames[serial] = f;
    expectPosesMatchFrames(after, 10);
}

TEST(LiveVideo, ALossyLinkCostsOnlyTheDamagedFrames) {
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    auto live = LiveVideo::open(udpUrl(port), {});
    ASSERT_TRUE(live) << live.message();
    net::UdpRelay relay(port, 0.05, 0.05, 7);
    ASSERT_GT(relay.port(), 0) << relay.error();
    std::this_thread::sleep_for(200ms);
    FmvStreamOptions o = flight(40);
    o.width = 320;
    o.height = 240;
    Sender sender(udpUrl(relay.port()), o);
    Seen seen;
    watchUntilSent(**live, seen, sender, 40, 15s);
    const net::RelayCounts r = relay.counts();
    EXPECT_GT(r.dropped, 0u);
    EXPECT_GT(r.corrupted, 0u);
    const LiveStats s = (*live)->stats();
    std::printf("[loss] relay: %llu datagrams, %llu dropped, %llu corrupted; received: %llu frames decoded, %llu shown, %llu lost, "
                "%llu concealed, %llu damaged packets, %llu KLV rejected, %llu continuity gaps, %llu frames damaged\n",
                (unsigned long long)r.received, (unsigned long long)r.dropped, (unsigned long long)r.corrupted,
                (unsigned long long)s.framesDecoded, (unsigned long long)s.framesShown, (unsigned long long)s.framesLost,
                (unsigned long long)s.framesConcealed, (unsigned long long)s.corruptPackets, (unsigned long long)s.klvRejected,
                (unsigned long long)s.continuityGaps, (unsigned long long)s.framesDamaged);
    EXPECT_GT(s.corruptPackets + s.framesLost + s.klvRejected, 0u) << "the damage was seen";
    EXPECT_GT(s.framesDecoded, 0u);
    EXPECT_LT(s.framesDecoded, 40u);
    // What is shown is whole: right size, and placed at its own time.
    for (const auto& [serial, f] : seen.frames) EXPECT_EQ(f.frame->rgba.size(), size_t(320 * 240 * 4));
    Seen posed;
    for (const auto& [serial, f] : seen.frames)
        if (f.pose) posed.frames[serial] = f;
    EXPECT_FALSE(posed.frames.empty());
}

/// Mean absolute difference, in levels, between a received frame and the fixture's frame n.
double meanDifference(const VideoFrame& f, int n) {
    const std::vector<uint8_t> want = fixtureFrame(n, f.width, f.height);
    if (want.size() != f.rgba.size()) return 255.0;
    double sum = 0.0;
    for (size_t i = 0; i < want.size(); i += 4)
        for (size_t c = 0; c < 3; ++c) sum += std::abs(int(want[i + c]) - int(f.rgba[i + c]));
    return sum / double(want.size() / 4 * 3);
}

// Datagrams dropped on the way: the frames they fell in (and those that refer to them) are
// marked damaged, found from the transport stream's continuity counters; every frame shown
// unmarked is whole (equals the frame sent, up to coding: 0.2 levels measured, a concealed one
// 0.3 to 1.4). With `skipDamaged` none is shown.
void expectDamageMarked(bool wholeFrames, bool skipDamaged) {
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    LiveOptions options;
    options.wholeFrames = wholeFrames;
    options.skipDamaged = skipDamaged;
    options.jitterSeconds = 0.05;
    auto live = LiveVideo::open(udpUrl(port), options);
    ASSERT_TRUE(live) << live.message();
    net::UdpRelay relay(port, 0.04, 0.0, 11);
    ASSERT_GT(relay.port(), 0) << relay.error();
    std::this_thread::sleep_for(200ms);
    FmvStreamOptions o = flight(60);
    o.fps = 15;
    o.width = 320;
    o.height = 240;
    Sender sender(udpUrl(relay.port()), o);
    Seen seen;
    watchUntilSent(**live, seen, sender, 60, 15s);
    const LiveStats s = (*live)->stats();
    EXPECT_GT(relay.counts().dropped, 0u);
    EXPECT_GT(s.continuityGaps, 0u);
    size_t whole = 0, damaged = 0;
    for (const auto& [serial, f] : seen.frames) {
        const int n = fixtureFrameNumber(f.frame->rgba, f.frame->width, f.frame->height);
        const double diff = n >= 0 ? meanDifference(*f.frame, n) : 255.0;
        EXPECT_FALSE(skipDamaged && f.damaged) << "frame " << n;
        if (f.damaged) {
            ++damaged;
            continue;
        }
        ++whole;
        EXPECT_GE(n, 0) << "an unmarked frame is whole";
        EXPECT_LT(diff, 0.5) << "frame " << n << " shown unmarked";
    }
    std::printf("[damage] %s, %s: %llu dropped: %llu gaps, %llu frames damaged, %llu lost; shown %zu whole, %zu damaged\n",
                wholeFrames ? "whole frames" : "parsed", skipDamaged ? "skip" : "show", (unsigned long long)relay.counts().dropped, (unsigned long long)s.continuityGaps,
                (unsigned long long)s.framesDamaged, (unsigned long long)s.framesLost, whole, damaged);
    EXPECT_GT(s.framesDamaged + s.framesLost, 0u);
    EXPECT_GT(whole, 10u);
}

TEST_P(LiveVideoParsing, FramesThatLostDataAreMarkedDamaged) { expectDamageMarked(GetParam(), false); }
TEST_P(LiveVideoParsing, FramesThatLostDataCanBeSkipped) { expectDamageMarked(GetParam(), true); }

TEST(LiveVideo, FourFeedsAtOnce) {
    std::vector<std::unique_ptr<LiveVideo>> lives;
    std::vector<int> ports;
    for (int i = 0; i < 4; ++i) {
        ports.push_back(net::freeUdpPort());
        ASSERT_GT(ports.back(), 0);
        auto live = LiveVideo::open(udpUrl(ports.back()), {});
        ASSERT_TRUE(live) << live.message();
        lives.push_back(std::move(*live));
    }
    std::this_thread::sleep_for(200ms);
    std::vector<std::unique_ptr<Sender>> senders;
    for (int i = 0; i < 4; ++i) {
        FmvStreamOptions o = flight(20);
        o.flightStart = 30.0 * i;   // four places on the lap
        senders.push_back(std::make_unique<Sender>(udpUrl(ports[size_t(i)]), o));
    }
    std::vector<Seen> seen(4);
    const auto end = std::chrono::steady_clock::now() + 8s;
    while (std::chrono::steady_clock::now() < end) {
        for (size_t i = 0; i < 4; ++i)
            if (auto f = lives[i]->due(wallClockSeconds())) seen[i].frames[f->frame->index] = *f;
        std::this_thread::sleep_for(5ms);
        bool all = true;
        for (auto& s : senders) all &= s->done.wait_for(0s) == std::future_status::ready;
        if (all && lives[0]->stats().secondsSinceData > 0.3) break;
    }
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(senders[i]->finish(), 20);
        EXPECT_GE(lives[i]->stats().framesDecoded, 19u) << "feed " << i;
        EXPECT_GE(seen[i].frames.size(), 8u) << "feed " << i;
        // Each feed's poses are its own part of the lap.
        ASSERT_FALSE(seen[i].frames.empty());
        const LiveFrame& f = seen[i].frames.begin()->second;
        ASSERT_TRUE(f.pose);
        const SensorPose first = SyntheticFlight::pose(30.0 * double(i));
        EXPECT_NEAR(f.pose->platformHeadingDeg, first.platformHeadingDeg, 10.0) << "feed " << i;
    }
}

TEST(LiveVideo, ARecordingPlaysBackTheFramesShownLive) {
    const auto dir = std::filesystem::temp_directory_path() / ("orbis-live-record-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string recording = (dir / "feed.ts").string();
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    LiveOptions options;
    options.recordPath = recording;
    options.maxQueuedFrames = 64;
    options.wholeFrames = true;
    Seen seen;
    {
        auto live = LiveVideo::open(udpUrl(port), options);
        ASSERT_TRUE(live) << live.message();
        std::this_thread::sleep_for(200ms);
        Sender sender(udpUrl(port), flight(25));
        watch(**live, seen, [&] { return sender.done.wait_for(0s) == std::future_status::ready; }, 10s);
        EXPECT_EQ(sender.finish(), 25);
        watch(**live, seen, [&] { return false; }, 500ms);
        EXPECT_EQ((*live)->stats().packetsRecorded, 50u);
    }   // closing the feed finishes the file
    auto file = VideoFile::open(recording);
    ASSERT_TRUE(file) << file.message();
    EXPECT_TRUE((*file)->info().hasKlv);
    EXPECT_EQ((*file)->frameCount(), 25u);
    auto timeline = FmvTimeline::fromKlv((*file)->klv(), recording);
    ASSERT_TRUE(timeline) << timeline.message();
    EXPECT_EQ(timeline->poses().size(), 25u);
    EXPECT_EQ(timeline->checksumRejected(), 0u);
    ASSERT_GE(seen.frames.size(), 10u);
    // The recording's frames by the number in their pictures.
    std::map<int, VideoFrame> recorded;
    for (size_t i = 0; i < (*file)->frameCount(); ++i) {
        auto frame = (*file)->decode(i);
        ASSERT_TRUE(frame) << frame.message();
        recorded[fixtureFrameNumber(frame->rgba, frame->width, frame->height)] = std::move(*frame);
    }
    const LiveFrame& firstLive = seen.frames.begin()->second;
    const int firstLiveNumber = fixtureFrameNumber(firstLive.frame->rgba, firstLive.frame->width, firstLive.frame->height);
    ASSERT_TRUE(recorded.count(firstLiveNumber));
    for (const auto& [serial, f] : seen.frames) {
        // The same frame of the flight in the recording: same picture, bit for bit, same time
        // from the first shown, same pose.
        const int n = fixtureFrameNumber(f.frame->rgba, f.frame->width, f.frame->height);
        ASSERT_TRUE(recorded.count(n)) << "frame " << n << " was shown live but not recorded";
        const VideoFrame* replay = &recorded[n];
        EXPECT_TRUE(replay->rgba == f.frame->rgba) << "frame " << n << " differs from the live one";
        EXPECT_NEAR(replay->time - recorded[firstLiveNumber].time, f.streamTime - firstLive.streamTime, 1e-3);
        const SensorPose p = timeline->poseAt(replay->time);
        ASSERT_TRUE(f.pose);
        EXPECT_NEAR(p.latDeg, f.pose->latDeg, 1e-9);
        EXPECT_NEAR(p.lonDeg, f.pose->lonDeg, 1e-9);
        EXPECT_NEAR(p.platformHeadingDeg, f.pose->platformHeadingDeg, 1e-9);
    }
    std::filesystem::remove_all(dir);
}

TEST(LiveVideo, RecordingStartedAndStoppedWhileLiveBeginsAtAKeyFrame) {
    const auto dir = std::filesystem::temp_directory_path() / ("orbis-live-record2-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string recording = (dir / "part.ts").string();
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    LiveOptions options;
    options.wholeFrames = true;
    options.maxQueuedFrames = 64;
    Seen seen;
    {
        auto live = LiveVideo::open(udpUrl(port), options);
        ASSERT_TRUE(live) << live.message();
        std::this_thread::sleep_for(200ms);
        Sender sender(udpUrl(port), flight(45));   // key frames at 0, 1, 2, 3, 4 s
        watch(**live, seen, [&] { return false; }, 1500ms);
        ASSERT_TRUE((*live)->record(recording));
        EXPECT_EQ((*live)->stats().recording, recording);
        // Stopped once thirty packets are in: the KLV of the second before the key frame, then
        // about ten frames with theirs (bounded: the sender's 4.5 s).
        watch(**live, seen, [&] { return (*live)->stats().packetsRecorded >= 30; }, 5s);
        ASSERT_TRUE((*live)->record(""));
        watch(**live, seen, [&] { return sender.done.wait_for(0s) == std::future_status::ready; }, 10s);
        EXPECT_TRUE((*live)->stats().recording.empty());
        EXPECT_FALSE((*live)->record((dir / "no-such-folder" / "x.ts").string()));
    }
    auto file = VideoFile::open(recording);
    ASSERT_TRUE(file) << file.message();
    // Asked for at about 1.5 s and stopped some packets later: the frames from the next key
    // frame to the stop, each one the live frame of the same number, with its KLV.
    ASSERT_GE((*file)->frameCount(), 4u);
    EXPECT_LT((*file)->frameCount(), 45u);
    auto first = (*file)->decode(0);
    ASSERT_TRUE(first) << first.message();
    const int firstNumber = fixtureFrameNumber(first->rgba, first->width, first->height);
    EXPECT_EQ(firstNumber % 10, 0) << "starts at a key frame";
    auto timeline = FmvTimeline::fromKlv((*file)->klv(), recording);
    ASSERT_TRUE(timeline) << timeline.message();
    EXPECT_GE(timeline->poses().size(), (*file)->frameCount());
    EXPECT_LE(timeline->poses().front().time, 1e-6) << "the KLV of the first frame is there";
    size_t compared = 0;
    for (size_t i = 0; i < (*file)->frameCount(); ++i) {
        auto replay = (*file)->decode(i);
        ASSERT_TRUE(replay) << replay.message();
        const int n = fixtureFrameNumber(replay->rgba, replay->width, replay->height);
        EXPECT_EQ(n, firstNumber + int(i));
        for (const auto& [serial, f] : seen.frames)
            if (fixtureFrameNumber(f.frame->rgba, f.frame->width, f.frame->height) == n) {
                EXPECT_TRUE(f.frame->rgba == replay->rgba) << "frame " << n;
                ++compared;
            }
    }
    EXPECT_GE(compared, 2u);
    std::filesystem::remove_all(dir);
}

/// A folder of its own for a test, removed with everything in it at the end.
struct ScratchDir {
    std::filesystem::path path;
    explicit ScratchDir(const std::string& name)
        : path(std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()))) {
        std::filesystem::create_directories(path);
    }
    ~ScratchDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
};

/// A feed recorded into `recording` that takes 0.5 s of silence for no signal and tries again
/// every 0.1 s.
LiveOptions recordedQuickly(const std::string& recording) {
    LiveOptions options;
    options.wholeFrames = true;
    options.noSignalSeconds = 0.5;
    options.retrySeconds = 0.1;
    options.recordPath = recording;
    return options;
}

// A sender that stops and comes back on a new clock while the feed is recorded: the file goes
// on, the second flight after the first with the silence between, every frame with its own
// KLV, and plays back through the file path.
TEST(LiveVideo, ARecordingGoesOnWhenTheStreamComesBack) {
    const ScratchDir dir("orbis-live-record4");
    const std::string recording = (dir.path / "both.ts").string();
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    auto live = LiveVideo::open(udpUrl(port), recordedQuickly(recording));
    ASSERT_TRUE(live) << live.message();
    std::this_thread::sleep_for(200ms);
    Seen seen;
    {
        Sender first(udpUrl(port), flight(20));
        EXPECT_EQ(first.finish(), 20);
    }
    watch(**live, seen, [&] { return (*live)->stats().state == LiveState::NoSignal; }, 5s);
    ASSERT_EQ((*live)->stats().state, LiveState::NoSignal);
    std::this_thread::sleep_for(300ms);
    {
        FmvStreamOptions o = flight(15);
        o.flightStart = 30.0;   // elsewhere on the flight, on a clock that starts again at 0
        Sender second(udpUrl(port), o);
        EXPECT_EQ(second.finish(), 15);
    }
    watch(**live, seen, [&] { return false; }, 500ms);
    EXPECT_GE((*live)->stats().reconnects, 1u);
    live->reset();   // closes the recording
    auto file = VideoFile::open(recording);
    ASSERT_TRUE(file) << file.message();
    ASSERT_EQ((*file)->frameCount(), 35u);
    auto timeline = FmvTimeline::fromKlv((*file)->klv(), recording);
    ASSERT_TRUE(timeline) << timeline.message();
    EXPECT_EQ(timeline->poses().size(), 35u);
    // Frames 0..19 of the first flight, then 0..14 of the second; the second starts after the
    // first ends plus the silence (over 0.5 s), and each frame has the pose of its own flight time.
    double lastTime = -1.0;
    for (size_t i = 0; i < 35; ++i) {
        auto frame = (*file)->decode(i);
        ASSERT_TRUE(frame) << frame.message();
        const int n = fixtureFrameNumber(frame->rgba, frame->width, frame->height);
        EXPECT_EQ(n, i < 20 ? int(i) : int(i) - 20) << "frame " << i;
        const double t = (*file)->frameTimes()[i];
        EXPECT_GT(t, lastTime) << "frame " << i;
        if (i == 20) {
            EXPECT_GT(t - lastTime, 0.5) << "the silence between";
        }
        lastTime = t;
        const SensorPose want = SyntheticFlight::pose((i < 20 ? 0.0 : 30.0) + double(n) / 10.0);
        const SensorPose got = timeline->poseAt(t);
        EXPECT_NEAR(got.latDeg, want.latDeg, 1e-6) << "frame " << i;
        EXPECT_NEAR(got.lonDeg, want.lonDeg, 1e-6) << "frame " << i;
    }
}

// Stop pressed while the feed has no signal closes the recording then (between attempts to open
// the stream again), not when data comes again: the file is whole while the layer lives on.
TEST(LiveVideo, ARecordingStoppedWithoutSignalIsClosedAtOnce) {
    const ScratchDir dir("orbis-live-record3");
    const std::string recording = (dir.path / "silent.ts").string();
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    auto live = LiveVideo::open(udpUrl(port), recordedQuickly(recording));
    ASSERT_TRUE(live) << live.message();
    std::this_thread::sleep_for(200ms);
    {
        Sender sender(udpUrl(port), flight(20));
        EXPECT_EQ(sender.finish(), 20);
    }
    Seen seen;
    watch(**live, seen, [&] { return (*live)->stats().state == LiveState::NoSignal; }, 5s);
    ASSERT_EQ((*live)->stats().state, LiveState::NoSignal);
    const uint64_t recorded = (*live)->stats().packetsRecorded;
    EXPECT_GE(recorded, 40u);   // 20 frames and their KLV
    ASSERT_TRUE((*live)->record(""));
    std::this_thread::sleep_for(4s);   // a silent attempt to open the stream again: noSignal + 2 s of probing at most
    auto file = VideoFile::open(recording);
    ASSERT_TRUE(file) << file.message();
    EXPECT_EQ((*file)->frameCount(), 20u) << "every frame recorded is in the file, the layer still open";
    live->reset();
}

// A host name that does not resolve: no signal, saying which host; the lookup runs off the
// feed's thread, so closing does not wait for the resolver.
TEST(LiveVideo, AHostThatDoesNotResolveIsNoSignalNamingIt) {
    LiveOptions options;
    options.noSignalSeconds = 0.5;
    options.retrySeconds = 0.1;
    auto live = LiveVideo::open("tcp://no-such-host.invalid:5600", options);
    ASSERT_TRUE(live) << live.message();
    const auto until = std::chrono::steady_clock::now() + 8s;
    while (std::chrono::steady_clock::now() < until && (*live)->stats().lastError.empty()) std::this_thread::sleep_for(20ms);
    const LiveStats s = (*live)->stats();
    EXPECT_EQ(s.state, LiveState::NoSignal);
    EXPECT_NE(s.lastError.find("no-such-host.invalid"), std::string::npos) << s.lastError;
    const auto closing = std::chrono::steady_clock::now();
    live->reset();
    EXPECT_LT(std::chrono::steady_clock::now() - closing, 1s);
}

TEST(LiveVideo, RefusesWhatIsNotALiveStream) {
    auto empty = LiveVideo::open("", {});
    ASSERT_FALSE(empty);
    EXPECT_NE(empty.message().find("a live stream is a URL"), std::string::npos) << empty.message();
    auto path = LiveVideo::open("flight.ts", {});
    ASSERT_FALSE(path);
    auto file = LiveVideo::open("file:///tmp/flight.ts", {});
    ASSERT_FALSE(file);
    EXPECT_NE(file.message().find("\"path\""), std::string::npos) << file.message();
    auto unknown = LiveVideo::open("nosuch://127.0.0.1:70/x", {});
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.message().find("cannot receive nosuch://"), std::string::npos) << unknown.message();
    EXPECT_NE(unknown.message().find("udp"), std::string::npos) << unknown.message();
    LiveOptions o;
    o.recordPath = "/nonexistent-folder/feed.ts";
    auto record = LiveVideo::open("udp://127.0.0.1:9", o);
    ASSERT_FALSE(record);
    EXPECT_NE(record.message().find("/nonexistent-folder/feed.ts"), std::string::npos) << record.message();
    o.recordPath.clear();
    o.jitterSeconds = -1.0;
    EXPECT_FALSE(LiveVideo::open("udp://127.0.0.1:9", o));
}

// MPEG-TS served over HTTP by FFmpeg's own HTTP server (the sender listens, answers one GET with
// an endless chunked response), and carried in RTP (payload type 33) to a bound receiver.
TEST(LiveVideo, ReceivesHttpFromAServer) {
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/feed.ts";
    FmvStreamOptions o = flight(25);
    o.listen = true;
    Sender sender(url, o);
    std::this_thread::sleep_for(200ms);
    LiveOptions options;
    options.wholeFrames = true;
    auto live = LiveVideo::open(url, options);
    ASSERT_TRUE(live) << live.message();
    Seen seen;
    watchUntilSent(**live, seen, sender, 25, 10s);
    expectWholeFlight((*live)->stats(), seen, 25, 8);
}

TEST(LiveVideo, ReceivesRtp) {
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    const std::string url = "rtp://127.0.0.1:" + std::to_string(port);
    LiveOptions options;
    options.wholeFrames = true;
    auto live = LiveVideo::open(url, options);
    ASSERT_TRUE(live) << live.message();
    std::this_thread::sleep_for(200ms);
    Sender sender(url, flight(30));
    Seen seen;
    watchUntilSent(**live, seen, sender, 30, 10s);
    expectWholeFlight((*live)->stats(), seen, 30, 10);
    EXPECT_EQ((*live)->stats().posesReceived, 30u);
}

TEST(LiveVideo, OnlyAConnectedProtocolCanWaitForItsReceiver) {
    FmvStreamOptions o = flight(1);
    o.listen = true;
    std::atomic<bool> stop{false};
    auto r = streamFmvFixture("udp://127.0.0.1:9", o, stop);
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("udp://127.0.0.1:9"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("wait for its receiver"), std::string::npos) << r.message();
}

class LiveVideoSilence : public testing::TestWithParam<const char*> {};
INSTANTIATE_TEST_SUITE_P(LiveVideo, LiveVideoSilence, testing::Values("udp://127.0.0.1:%d", "srt://127.0.0.1:%d?mode=listener"),
                         [](const auto& info) { return std::string(info.param).substr(0, 3); });

// Nothing ever sent: UDP waiting for datagrams, SRT listening for a caller that never comes.
TEST_P(LiveVideoSilence, IsConnectingThenNoSignalAndClosesWithoutBlocking) {
    const int port = net::freeUdpPort();
    ASSERT_GT(port, 0);
    char url[128];
    std::snprintf(url, sizeof url, GetParam(), port);
    LiveOptions options;
    options.noSignalSeconds = 0.5;
    options.retrySeconds = 0.1;
    const auto start = std::chrono::steady_clock::now();
    auto closing = start;
    {
        auto live = LiveVideo::open(url, options);
        ASSERT_TRUE(live) << live.message();
        EXPECT_FALSE((*live)->due(wallClockSeconds()));
        const auto until = std::chrono::steady_clock::now() + 6s;
        while (std::chrono::steady_clock::now() < until && (*live)->stats().state != LiveState::NoSignal)
            std::this_thread::sleep_for(20ms);
        EXPECT_EQ((*live)->stats().state, LiveState::NoSignal);
        EXPECT_FALSE((*live)->due(wallClockSeconds()));
        closing = std::chrono::steady_clock::now();
    }   // closing does not wait for the stream
    EXPECT_LT(std::chrono::steady_clock::now() - closing, 1s);
    EXPECT_LT(std::chrono::steady_clock::now() - start, 7s);
}

}  // namespace
}  // namespace orbis::fmv
