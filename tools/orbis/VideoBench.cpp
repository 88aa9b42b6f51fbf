// orbis bench --video FILE: the FMV layer's CPU side on one video (no GPU).
//
//   KLV: its packets decoded (ST 0601 with checksums) repeatedly: packets per second.
//   Playback: every frame decoded in order (the decode-ahead path): ms per frame.
//   Seek: frames in a seeded random order, each decoded exactly from a cold decoder position
//   (the scrub path): ms per seek, median and 95th percentile.
#include "tools/orbis/Commands.h"

#include "layers/fmv/FmvTimeline.h"
#include "formats/fmv/KlvFile.h"
#include "layers/fmv/VideoFile.h"
#include "tools/orbis/Session.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>

namespace orbis::cli {
namespace {

using Clock = std::chrono::steady_clock;

double ms(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(p * double(v.size() - 1) + 0.5))];
}

}  // namespace

int videoBench(const std::string& file, long seeks) {
    const auto t0 = Clock::now();
    auto opened = fmv::VideoFile::open(file);
    if (!opened) return badInput(opened.message());
    const auto t1 = Clock::now();
    fmv::VideoFile& video = **opened;
    const fmv::VideoInfo& info = video.info();
    std::printf("orbis bench --video %s  %s %dx%d, %zu frames, %.3g fps, %zu KLV packets  (CPU only)\n", file.c_str(),
                info.codec.c_str(), info.width, info.height, video.frameCount(), info.frameRate, video.klv().size());
    std::printf("open + index (one pass over the container): %.1f ms\n", ms(t0, t1));

    // KLV: decode every packet, repeated to at least 200 000 packets or 0.5 s.
    if (!video.klv().empty()) {
        size_t decoded = 0, runs = 0;
        const auto k0 = Clock::now();
        while (decoded < 200000 && ms(k0, Clock::now()) < 500.0) {
            for (const fmv::TimedKlv& k : video.klv()) decoded += fmv::decodeKlvStream(k.bytes).decodedCount();
            ++runs;
        }
        const double seconds = ms(k0, Clock::now()) * 1e-3;
        std::printf("KLV: %.3g packets/s decoded (ST 0601 with checksums; %zu runs over the file)\n", double(decoded) / seconds,
                    runs);
        const auto p0 = Clock::now();
        auto timeline = fmv::FmvTimeline::fromKlv(video.klv(), file);
        std::printf("poses: %s in %.2f ms\n",
                    timeline ? (std::to_string(timeline->poses().size()) + " from the KLV").c_str() : timeline.message().c_str(),
                    ms(p0, Clock::now()));
    }

    // Playback: every frame in order.
    std::vector<double> frameMs;
    for (size_t i = 0; i < video.frameCount(); ++i) {
        const auto a = Clock::now();
        auto f = video.decode(i);
        if (!f) return badInput(f.message());
        frameMs.push_back(ms(a, Clock::now()));
    }
    std::printf("playback: %.2f ms/frame median, %.2f p95 (decode + RGBA; %zu frames)\n", percentile(frameMs, 0.5),
                percentile(frameMs, 0.95), frameMs.size());

    // Seeks: random frames, exact.
    std::mt19937 rng(1);
    std::uniform_int_distribution<size_t> pick(0, video.frameCount() - 1);
    std::vector<double> seekMs;
    const uint64_t decodedBefore = video.framesDecoded();
    for (long s = 0; s < seeks; ++s) {
        const size_t i = pick(rng);
        const auto a = Clock::now();
        auto f = video.decode(i);
        if (!f) return badInput(f.message());
        seekMs.push_back(ms(a, Clock::now()));
    }
    std::printf("seek (exact frame, random order): %.2f ms median, %.2f p95, %.1f frames decoded a seek (%ld seeks)\n",
                percentile(seekMs, 0.5), percentile(seekMs, 0.95),
                double(video.framesDecoded() - decodedBefore) / double(std::max(seeks, 1L)), seeks);
    return kOk;
}

}  // namespace orbis::cli
