#pragma once
// A UAV video file through FFmpeg (libavformat, libavcodec, libswscale), CPU only (no Vulkan):
// its video stream's frames indexed by presentation time, and its KLV data stream (MISB ST 0601
// in an MPEG-TS, synchronous stream type 0x15 or asynchronous 0x06) demuxed with each packet's
// time. Opening reads the container once, without decoding, to build the frame index and
// collect the KLV packets; frames are then decoded on demand into RGBA, exactly the frame asked
// for: the decoder seeks to the key frame at or before it and decodes forward, and runs on
// from where it is when the frame asked for is just ahead (playback).
//
// Times are seconds on the video's own clock, from its first frame (frame 0 at 0 s).
//
//   auto video = fmv::VideoFile::open("flight.ts");      // Result: a clear error on bad input
//   for (const fmv::TimedKlv& k : (*video)->klv()) decode(k.bytes);
//   auto frame = (*video)->decode((*video)->frameAt(12.5));

#include "base/Result.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace orbis::fmv {

struct VideoInfo {
    int width = 0, height = 0;
    double duration = 0.0;    ///< seconds from the first frame to the end of the last
    double frameRate = 0.0;   ///< frames a second (the stream's average)
    std::string codec;        ///< e.g. "h264"
    bool hasKlv = false;   ///< a KLV data stream (synchronous or asynchronous: libavformat hides which)
};

/// One KLV data packet (an AVPacket of the data stream: one or more KLV sets) with its time.
struct TimedKlv {
    double time = 0.0;   ///< seconds on the video's clock (the packet's PTS, else DTS)
    std::vector<uint8_t> bytes;
};

/// One decoded frame, RGBA 8 bits a channel, rows top to bottom.
struct VideoFrame {
    size_t index = 0;
    double time = 0.0;
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;
};

class VideoFile {
public:
    /// Limits on what opening collects: a file beyond them is refused with a clear message.
    static constexpr size_t kMaxFrames = size_t(1) << 22;        // 38 hours at 30 fps
    static constexpr size_t kMaxKlvBytes = size_t(256) << 20;   // all KLV packets together
    static constexpr int kMaxDimension = 16384;

    /// Opens `path` and indexes it. Errors name the file: not a media file, no video stream,
    /// no decoder for its codec, frames without time stamps, over the limits above.
    static Result<std::unique_ptr<VideoFile>> open(const std::string& path);
    ~VideoFile();
    VideoFile(const VideoFile&) = delete;
    VideoFile& operator=(const VideoFile&) = delete;

    const std::string& path() const { return path_; }
    const VideoInfo& info() const { return info_; }
    /// Every frame's time, increasing (presentation order).
    const std::vector<double>& frameTimes() const { return frameTimes_; }
    size_t frameCount() const { return frameTimes_.size(); }
    /// The KLV data packets in time order (empty without a KLV stream).
    const std::vector<TimedKlv>& klv() const { return klv_; }

    /// The frame shown at time `t`: the last that starts at or before it (0 before the first).
    size_t frameAt(double t) const;
    /// Decodes frame `index` (exact). Not thread-safe: one thread at a time per VideoFile.
    Result<VideoFrame> decode(size_t index);
    /// Frames decoded since opening, and seeks made (for tests and stats).
    uint64_t framesDecoded() const { return decoded_; }
    uint64_t seeks() const { return seeks_; }

private:
    VideoFile() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::string path_;
    VideoInfo info_;
    std::vector<double> frameTimes_;
    std::vector<int64_t> framePts_;      // stream time base, presentation order
    std::vector<uint8_t> frameIsKey_;
    std::vector<TimedKlv> klv_;
    uint64_t decoded_ = 0, seeks_ = 0;
};

}  // namespace orbis::fmv
