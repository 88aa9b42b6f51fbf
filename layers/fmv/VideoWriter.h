#pragma once
// Writes an MPEG-TS with an H.264 video stream and a KLV data stream (synchronous, stream type
// 0x15, or asynchronous 0x06) through FFmpeg, to a file or streamed live to a URL: the FMV
// fixtures of the tests and of `orbis-make-fmv`. `ffmpeg -f data` writes bin_data, not KLV, so fixtures are made here.
//
//   auto w = fmv::VideoWriter::create("flight.ts", {.width = 320, .height = 240, .fps = 10});
//   (*w)->writeKlv(0.0, packet);          // before or with the frame it belongs to
//   (*w)->writeFrame(rgba);               // frame i is at i / fps seconds
//   (*w)->close();

#include "base/Result.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>

struct AVPacket;

namespace orbis::fmv {

struct VideoWriteOptions {
    int width = 320, height = 240;   ///< even numbers (4:2:0)
    int fps = 10;
    int gop = 10;                    ///< a key frame every this many frames
    bool withVideo = true;           ///< false: a KLV stream alone (tests of the error it gives)
    bool withKlv = true;
    bool klvSynchronous = true;      ///< stream type 0x15 (else 0x06, SMPTE RP 217)
    int crf = 18;                    ///< H.264 quality (lower: better)
    /// A live stream (`path` a URL such as udp://127.0.0.1:5600 or tcp://...?listen=1): no
    /// encoder delay (x264's zerolatency), every packet written out as it is made, UDP datagrams
    /// of seven TS packets (1316 bytes) unless the URL says otherwise; rtp:// carries the
    /// MPEG-TS in RTP (payload type 33, RFC 2250).
    bool live = false;
    /// Live: wait for one receiver to connect instead of sending to it: tcp:// (listen=1),
    /// srt:// (mode=listener), http:// (FFmpeg's HTTP server answers one GET with the stream).
    bool listen = false;
    /// Polled while a live stream waits (for a receiver, on a full socket): true gives up.
    std::function<bool()> interrupted;
};

class VideoWriter {
public:
    static Result<std::unique_ptr<VideoWriter>> create(const std::string& path, const VideoWriteOptions& options);
    ~VideoWriter();
    VideoWriter(const VideoWriter&) = delete;
    VideoWriter& operator=(const VideoWriter&) = delete;

    /// The next frame, width x height RGBA rows top to bottom.
    Result<void> writeFrame(std::span<const uint8_t> rgba);
    /// A KLV packet at `time` seconds (the video's clock; frames are at i / fps).
    Result<void> writeKlv(double time, std::span<const uint8_t> bytes);
    /// Flushes the encoder and writes the trailer; the destructor does it too, silently.
    Result<void> close();
    int framesWritten() const { return frames_; }

private:
    VideoWriter() = default;
    Result<void> drain(bool flush);
    int write(AVPacket* packet);
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::string path_;
    VideoWriteOptions options_;
    int frames_ = 0, klvPackets_ = 0;
    bool closed_ = false;
};

}  // namespace orbis::fmv
