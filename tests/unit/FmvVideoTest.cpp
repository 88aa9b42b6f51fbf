// FMV video through FFmpeg: an MPEG-TS with H.264 frames and a KLV stream written by
// VideoWriter, read back by VideoFile (frame index, exact random access, KLV packets and their
// times), and the clear errors for a video without KLV, KLV without video and files that are
// not videos; the synthetic flight's poses over time (FmvTimeline) and decoding ahead
// (FramePrefetcher).
#include "layers/fmv/FmvTimeline.h"
#include "layers/fmv/FramePrefetcher.h"
#include "formats/fmv/St0601Encode.h"
#include "layers/fmv/SyntheticFlight.h"
#include "layers/fmv/VideoFile.h"
#include "layers/fmv/VideoWriter.h"
#include "tests/support/ProcessTempDir.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

namespace orbis::fmv {
namespace {

constexpr int kW = 160, kH = 96;

std::filesystem::path dir() { return test::processTempDir("orbis-fmv-video"); }

// Frame n: a checkerboard, with n in binary as 8 blocks of 16 x 16 along the top row (white 1,
// black 0), big enough to survive the compression.
std::vector<uint8_t> frameImage(int n, int kW = fmv::kW, int kH = fmv::kH) {
    std::vector<uint8_t> rgba(size_t(kW) * kH * 4);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            uint8_t* p = &rgba[(size_t(y) * kW + x) * 4];
            uint8_t v = ((x / 20 + y / 20) % 2) ? 170 : 90;
            if (y < 16 && x < 8 * 16) v = (n >> (x / 16)) & 1 ? 255 : 0;
            p[0] = p[1] = p[2] = v;
            p[3] = 255;
        }
    return rgba;
}

int frameNumber(const VideoFrame& f) {
    int n = 0;
    for (int bit = 0; bit < 8; ++bit) {
        const uint8_t v = f.rgba[(size_t(8) * f.width + bit * 16 + 8) * 4];
        if (v > 128) n |= 1 << bit;
    }
    return n;
}

std::vector<uint8_t> klvBytes(int n) {
    std::vector<uint8_t> b(24);
    for (size_t i = 0; i < b.size(); ++i) b[i] = uint8_t(n * 3 + int(i));
    return b;
}

/// Frames numbered from `first`, width x height.
std::string writeVideo(const std::string& name, int frames, VideoWriteOptions o = {}, int first = 0, int width = kW,
                       int height = kH) {
    o.width = width;
    o.height = height;
    const std::string path = (dir() / name).string();
    auto w = VideoWriter::create(path, o);
    EXPECT_TRUE(w.ok()) << w.message();
    if (!w) return path;
    for (int i = 0; i < frames; ++i) {
        if (o.withKlv) {
            EXPECT_TRUE((*w)->writeKlv(double(i) / o.fps, klvBytes(i)).ok());
        }
        if (o.withVideo) {
            EXPECT_TRUE((*w)->writeFrame(frameImage(first + i, o.width, o.height)).ok());
        }
    }
    auto closed = (*w)->close();
    EXPECT_TRUE(closed.ok()) << closed.message();
    return path;
}

TEST(FmvVideo, FramesAndKlvComeBackWithTheirTimes) {
    for (bool synchronous : {true, false}) {
        SCOPED_TRACE(synchronous ? "synchronous KLV" : "asynchronous KLV");
        VideoWriteOptions o;
        o.fps = 10;
        o.gop = 10;
        o.klvSynchronous = synchronous;
        const std::string path = writeVideo(synchronous ? "sync.ts" : "async.ts", 35, o);
        auto v = VideoFile::open(path);
        ASSERT_TRUE(v.ok()) << v.message();
        VideoFile& video = **v;
        EXPECT_EQ(video.info().width, kW);
        EXPECT_EQ(video.info().height, kH);
        EXPECT_EQ(video.info().codec, "h264");
        EXPECT_NEAR(video.info().frameRate, 10.0, 1e-6);
        EXPECT_NEAR(video.info().duration, 3.5, 1e-6);
        ASSERT_EQ(video.frameCount(), 35u);
        for (size_t i = 0; i < 35; ++i) EXPECT_NEAR(video.frameTimes()[i], 0.1 * double(i), 1e-6);
        EXPECT_TRUE(video.info().hasKlv);
        ASSERT_EQ(video.klv().size(), 35u);
        for (size_t i = 0; i < 35; ++i) {
            EXPECT_NEAR(video.klv()[i].time, 0.1 * double(i), 1e-4);
            EXPECT_EQ(video.klv()[i].bytes, klvBytes(int(i))) << "packet " << i;
        }
        EXPECT_EQ(video.frameAt(-1.0), 0u);
        EXPECT_EQ(video.frameAt(0.0), 0u);
        EXPECT_EQ(video.frameAt(1.25), 12u);
        EXPECT_EQ(video.frameAt(1e9), 34u);
    }
}

TEST(FmvVideo, EveryFrameDecodesExactlyInAnyOrder) {
    VideoWriteOptions o;
    o.fps = 10;
    o.gop = 8;
    const std::string path = writeVideo("random-access.ts", 40, o);
    auto v = VideoFile::open(path);
    ASSERT_TRUE(v.ok()) << v.message();
    VideoFile& video = **v;
    // Playback: one seek to start, then each frame decodes once.
    for (size_t i = 0; i < 40; ++i) {
        auto f = video.decode(i);
        ASSERT_TRUE(f.ok()) << f.message();
        EXPECT_EQ(frameNumber(*f), int(i));
        EXPECT_EQ(f->width, kW);
        EXPECT_NEAR(f->time, 0.1 * double(i), 1e-6);
    }
    EXPECT_EQ(video.seeks(), 1u);
    EXPECT_EQ(video.framesDecoded(), 40u);
    // Scrubbing: any order, each frame exact, decoding from the key frame at or before it.
    std::mt19937 rng(7);
    std::vector<size_t> order(40);
    for (size_t i = 0; i < 40; ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    const uint64_t before = video.framesDecoded();
    for (size_t i : order) {
        auto f = video.decode(i);
        ASSERT_TRUE(f.ok()) << f.message();
        EXPECT_EQ(frameNumber(*f), int(i)) << "asked for frame " << i;
    }
    EXPECT_LE(video.framesDecoded() - before, 40u * 8u);   // never more than a GOP a frame
    EXPECT_FALSE(video.decode(40).ok());
}

TEST(FmvVideo, AVideoReplacedWhileOpenReadsOnOrSaysItWasRewritten) {
    VideoWriteOptions o;
    o.fps = 10;
    o.gop = 5;
    const auto copyBytes = [](const std::string& from, const std::string& to) {   // in place: same inode
        std::ifstream in(from, std::ios::binary);
        std::ofstream out(to, std::ios::binary | std::ios::trunc);
        out << in.rdbuf();
    };
    // Renamed over: the open handle keeps the file it opened, frames stay this file's.
    {
        const std::string path = writeVideo("replaced.ts", 20, o);
        auto v = VideoFile::open(path);
        ASSERT_TRUE(v.ok()) << v.message();
        ASSERT_TRUE((*v)->decode(3).ok());
        std::filesystem::rename(writeVideo("other.ts", 30, o, 100, 2 * kW, 2 * kH), path);
        for (size_t i : {15u, 2u, 19u}) {
            auto f = (*v)->decode(i);
            ASSERT_TRUE(f.ok()) << f.message();
            EXPECT_EQ(frameNumber(*f), int(i));
            EXPECT_EQ(f->width, kW);
        }
    }
    // Rewritten in place by another video (other size, other frames): said, never decoded.
    {
        const std::string path = writeVideo("rewritten.ts", 20, o);
        auto v = VideoFile::open(path);
        ASSERT_TRUE(v.ok()) << v.message();
        ASSERT_TRUE((*v)->decode(3).ok());
        const auto sizeThen = std::filesystem::file_size(path);
        copyBytes(writeVideo("bigger.ts", 30, o, 100, 2 * kW, 2 * kH), path);
        for (size_t i : {15u, 4u}) {
            auto f = (*v)->decode(i);
            ASSERT_FALSE(f.ok());
            EXPECT_EQ(f.message(), path + ": the file was rewritten since it was opened (" +
                                       std::to_string(sizeThen) + " bytes then, " +
                                       std::to_string(std::filesystem::file_size(path)) +
                                       " now); open the scene again to read the new file");
        }
    }
    // Appended to (a recording still being written): the frames indexed at open read on.
    {
        const std::string path = writeVideo("growing.ts", 20, o);
        const std::string more = writeVideo("more.ts", 10, o, 20);
        auto v = VideoFile::open(path);
        ASSERT_TRUE(v.ok()) << v.message();
        {
            std::ifstream in(more, std::ios::binary);
            std::ofstream out(path, std::ios::binary | std::ios::app);
            out << in.rdbuf();
        }
        auto f = (*v)->decode(17);
        ASSERT_TRUE(f.ok()) << f.message();
        EXPECT_EQ(frameNumber(*f), 17);
    }
}

TEST(FmvVideo, VideoWithoutKlvAndKlvWithoutVideo) {
    VideoWriteOptions noKlv;
    noKlv.withKlv = false;
    auto plain = VideoFile::open(writeVideo("plain.ts", 5, noKlv));
    ASSERT_TRUE(plain.ok()) << plain.message();
    EXPECT_FALSE((*plain)->info().hasKlv);
    EXPECT_TRUE((*plain)->klv().empty());

    VideoWriteOptions noVideo;
    noVideo.withVideo = false;
    const std::string path = writeVideo("klv-only.ts", 5, noVideo);
    auto klvOnly = VideoFile::open(path);
    ASSERT_FALSE(klvOnly.ok());
    EXPECT_NE(klvOnly.message().find(path), std::string::npos) << klvOnly.message();
    EXPECT_NE(klvOnly.message().find("KLV metadata but no video stream"), std::string::npos) << klvOnly.message();
}

TEST(FmvVideo, FilesThatAreNotVideosGiveClearErrors) {
    const auto write = [](const std::string& name, const std::vector<uint8_t>& bytes) {
        const std::string p = (dir() / name).string();
        std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        return p;
    };
    std::mt19937 rng(3);
    std::vector<uint8_t> noise(20000);
    for (auto& b : noise) b = uint8_t(rng());
    for (const std::string& p : {write("empty.ts", {}), write("noise.ts", noise), (dir() / "missing.ts").string()}) {
        auto v = VideoFile::open(p);
        ASSERT_FALSE(v.ok()) << p;
        EXPECT_EQ(v.message().rfind(p, 0), 0u) << v.message();
    }
    // A truncated video: what is there is indexed and decodes; nothing crashes.
    const std::string whole = writeVideo("whole.ts", 20);
    std::ifstream in(whole, std::ios::binary);
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    bytes.resize(bytes.size() / 2);
    auto half = VideoFile::open(write("half.ts", bytes));
    if (half.ok()) {
        EXPECT_LT((*half)->frameCount(), 20u);
        for (size_t i = 0; i < (*half)->frameCount(); ++i) (void)(*half)->decode(i);
    }
    // Writer argument checks.
    VideoWriteOptions odd;
    odd.width = 15;
    EXPECT_FALSE(VideoWriter::create((dir() / "odd.ts").string(), odd).ok());
}

}  // namespace
}  // namespace orbis::fmv

// ---------------------------------------------------------------------------------------------
// The synthetic flight's video: poses over time from its KLV, and frames decoded ahead.
namespace orbis::fmv {
namespace {

std::string writeFlight(const std::string& name, int frames) {
    VideoWriteOptions o;
    o.width = kW;
    o.height = kH;
    o.fps = 10;
    const std::string path = (dir() / name).string();
    auto w = VideoWriter::create(path, o);
    EXPECT_TRUE(w.ok()) << w.message();
    for (int i = 0; i < frames; ++i) {
        EXPECT_TRUE((*w)->writeKlv(i / 10.0, encodeSt0601(SyntheticFlight::packet(i / 10.0))).ok());
        EXPECT_TRUE((*w)->writeFrame(frameImage(i)).ok());
    }
    EXPECT_TRUE((*w)->close().ok());
    return path;
}

TEST(FmvTimeline, PosesOfTheFlightFromItsKlv) {
    auto video = VideoFile::open(writeFlight("flight.ts", 20));
    ASSERT_TRUE(video.ok()) << video.message();
    auto timeline = FmvTimeline::fromKlv((*video)->klv(), "flight.ts");
    ASSERT_TRUE(timeline.ok()) << timeline.message();
    EXPECT_EQ(timeline->poses().size(), 20u);
    EXPECT_EQ(timeline->checksumRejected(), 0u);
    ASSERT_TRUE(timeline->videoStartUtc());
    EXPECT_NEAR(*timeline->videoStartUtc(), double(SyntheticFlight::kStartUs) * 1e-6, 1e-4);
    // Between packets: the flight's own pose, to within ST 0601's steps and the interpolation.
    for (double t : {0.0, 0.05, 0.73, 1.9, 5.0}) {
        const SensorPose got = timeline->poseAt(t), want = SyntheticFlight::pose(std::min(t, 1.9));
        const glm::dvec3 a = SensorCamera(got).position(), b = SensorCamera(want).position();
        EXPECT_LT(glm::length(a - b), 0.5) << "t = " << t;
        EXPECT_NEAR(got.platformHeadingDeg, want.platformHeadingDeg, 0.01) << "t = " << t;
        EXPECT_NEAR(got.sensorAzimuthDeg, want.sensorAzimuthDeg, 0.01) << "t = " << t;
        EXPECT_NEAR(got.sensorElevationDeg, want.sensorElevationDeg, 0.01) << "t = " << t;
    }
    // The sensor model against the corners the packets carry (made on the terrain, compared on
    // the frame centre's height: a degree or two); a producer with the azimuth's sign flipped
    // puts them tens of degrees off.
    const CornerCheck& check = timeline->cornerCheck();
    EXPECT_EQ(check.corners, 80u);
    EXPECT_LT(check.medianDegrees, 3.0);   // 1.8 here: the relief at grazing corners
    EXPECT_DOUBLE_EQ(check.medianFovDegrees, SyntheticFlight::kHfov);
    std::vector<std::pair<double, St0601Packet>> flipped;
    for (int i = 0; i < 20; ++i) {
        St0601Packet p = SyntheticFlight::packet(i / 10.0);
        p.sensorRelativeAzimuthDeg = 360.0 - *p.sensorRelativeAzimuthDeg;
        flipped.emplace_back(i / 10.0, p);
    }
    auto wrong = FmvTimeline::fromPackets(flipped, "flipped");
    ASSERT_TRUE(wrong.ok());
    EXPECT_GT(wrong->cornerCheck().medianDegrees, 10.0);
    // A packet with a wrong checksum is left out and counted; nothing usable is an error.
    std::vector<TimedKlv> packets = (*video)->klv();
    packets[3].bytes[20] ^= 0x40;
    auto damaged = FmvTimeline::fromKlv(packets, "damaged.ts");
    ASSERT_TRUE(damaged.ok()) << damaged.message();
    EXPECT_EQ(damaged->checksumRejected(), 1u);
    EXPECT_EQ(damaged->poses().size(), 19u);
    std::vector<TimedKlv> junk{{0.0, std::vector<uint8_t>(40, 0x55)}};
    auto none = FmvTimeline::fromKlv(junk, "junk.ts");
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.message().find("junk.ts: no usable KLV packet"), std::string::npos) << none.message();
    St0601Packet noFov;
    noFov.sensorLatitudeDeg = 1.0;
    noFov.sensorLongitudeDeg = 2.0;
    noFov.sensorEllipsoidHeight = 100.0;
    auto incomplete = FmvTimeline::fromPackets({{0.0, noFov}}, "poses.csv");
    ASSERT_FALSE(incomplete.ok());
    EXPECT_NE(incomplete.message().find("field of view"), std::string::npos) << incomplete.message();
}

TEST(FmvTimeline, InterpolationTakesTheShortWayRound) {
    SensorPose a, b;
    a.lonDeg = 179.9, b.lonDeg = -179.9;
    a.platformHeadingDeg = 350.0, b.platformHeadingDeg = 10.0;
    a.sensorAzimuthDeg = 5.0, b.sensorAzimuthDeg = 355.0;
    const SensorPose m = interpolate(a, b, 0.5);
    EXPECT_NEAR(std::abs(m.lonDeg), 180.0, 1e-9);
    EXPECT_NEAR(std::fmod(m.platformHeadingDeg, 360.0), 0.0, 1e-9);
    EXPECT_NEAR(std::fmod(m.sensorAzimuthDeg, 360.0), 0.0, 1e-9);
    const SensorPose q = interpolate(a, b, 0.25);
    EXPECT_NEAR(q.lonDeg, 179.95, 1e-9);
    EXPECT_NEAR(q.platformHeadingDeg, 355.0, 1e-9);
}

TEST(FramePrefetcher, DecodesAheadAndFollowsJumps) {
    auto video = VideoFile::open(writeVideo("prefetch.ts", 40));
    ASSERT_TRUE(video.ok()) << video.message();
    jobs::ThreadPool pool(1, "test-decode");
    FramePrefetcher frames(std::shared_ptr<VideoFile>(std::move(*video)), pool, 4);
    const auto show = [&](size_t index, bool backward = false) {
        for (int tries = 0; tries < 2000; ++tries) {
            if (const VideoFrame* f = frames.request(index, backward)) return frameNumber(*f);
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        return -1;
    };
    for (size_t i = 0; i < 12; ++i) EXPECT_EQ(show(i), int(i));
    EXPECT_LE(frames.framesQueued(), 5u);
    EXPECT_EQ(show(31), 31);   // a jump
    EXPECT_EQ(show(32), 32);
    for (size_t i = 20; i > 14; --i) EXPECT_EQ(show(i, true), int(i));   // playing backwards
    EXPECT_EQ(show(1000), 39);   // past the end: the last frame
    EXPECT_TRUE(frames.error().empty());
}

}  // namespace
}  // namespace orbis::fmv
