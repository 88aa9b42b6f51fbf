#pragma once
// A live UAV video stream through FFmpeg's network demuxers (udp://, including multicast
// groups, tcp://, http://, srt:// and rtp:// where the Debian build has them): MPEG-TS with an
// H.264 (or any decodable) video stream and a MISB ST 0601 KLV stream, synchronous (0x15) or
// asynchronous (0x06). CPU only (no Vulkan).
//
// One thread a stream demuxes and decodes as packets arrive: frames into RGBA, KLV packets into
// sensor poses on the stream's clock. Every wait on the network is bounded (FFmpeg's interrupt
// callback): no packet for `noSignalSeconds` is "no signal"; the stream is then opened again
// every `retrySeconds` until it comes back, by itself.
//
// The main thread asks once a frame for the frame due now (due()): a small jitter buffer plays
// frames out at their stream time plus the smallest transit seen (arrival - stream time) plus
// `jitterSeconds`, so frames that arrive in bursts are shown evenly, and the newest due frame
// wins (older ones are skipped, never shown late). Each frame comes with the pose at its own
// time: the KLV poses around the frame's presentation time interpolated (not the latest
// packet); after the last packet the last pose holds for up to a second.
//
// Damage costs only what it touches. A datagram lost on the way leaves a gap in the transport
// stream's continuity counters: the video frame it fell in is known (FFmpeg 5.1's demuxer sees
// the gap but its parser drops the mark; LiveVideo.cpp catches the demuxer's report) and is
// either shown as the decoder conceals it, counted as damaged (`skipDamaged` false, the default),
// or left out with the frames that refer to it up to the next key frame (`skipDamaged`). A
// packet the decoder refuses is left out the same way; a KLV packet that fails its checksum or
// does not decode is left out and counted.
//
// Recording: with `recordPath` (or record() at any time), every packet is also written as
// received (no re-encoding) into an MPEG-TS that VideoFile plays back through the file path,
// from a key frame on. A stream that comes back (a new connection, a new clock) goes on in the
// same file, its times moved to follow what was written after the silence.
//
//   auto live = fmv::LiveVideo::open("udp://127.0.0.1:5600", {});
//   if (auto f = (*live)->due(wallClockSeconds())) show(*f->frame, f->pose);

#include "base/Result.h"
#include "layers/fmv/FmvTimeline.h"
#include "layers/fmv/SensorModel.h"
#include "layers/fmv/VideoFile.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace orbis::fmv {

enum class LiveState {
    Connecting,   ///< not yet received a frame
    Live,         ///< frames arriving
    NoSignal,     ///< nothing for noSignalSeconds (or the stream closed): opening it again
};
const char* toString(LiveState state);

struct LiveOptions {
    double jitterSeconds = 0.1;     ///< playout delay over the smallest transit seen
    double noSignalSeconds = 2.0;   ///< silence that counts as no signal (and ends a wait)
    double retrySeconds = 0.5;      ///< between attempts to open the stream again
    size_t maxQueuedFrames = 8;     ///< decoded frames waiting for their time; older ones dropped
    std::string recordPath;         ///< record the stream as received to this MPEG-TS
    /// The sender puts each video frame whole in one PES packet (FFmpeg's muxer, most UAV
    /// encoders): frames go to the decoder as they arrive. Otherwise FFmpeg's parser finds the
    /// frames, and holds each until the next one starts: a frame interval more latency, and the
    /// last frame before a stream stops is not shown.
    bool wholeFrames = false;
    /// A video frame that lost data on the way is left out, with the frames after it up to the
    /// next key frame (they refer to it), instead of shown as the decoder conceals it.
    bool skipDamaged = false;
    /// Makes the geoid model for ST 0601 altitudes above mean sea level; called on the stream's
    /// own thread (coordinate transformations are used by one thread).
    std::function<GeoidHeight()> makeGeoid;
};

/// Counts since the stream was opened (all sessions together).
struct LiveStats {
    LiveState state = LiveState::Connecting;
    uint64_t bytes = 0;                ///< payload bytes of the packets demuxed
    double bitsPerSecond = 0.0;        ///< over the last two seconds
    double secondsSinceData = 0.0;     ///< since the last packet (since opening before one)
    uint64_t framesDecoded = 0, framesShown = 0;
    uint64_t framesSkipped = 0;        ///< decoded but superseded before their time, or over the queue
    uint64_t framesLost = 0;           ///< gaps in the frames' times (frames never received)
    uint64_t corruptPackets = 0;       ///< flagged corrupt by the demuxer or refused by the decoder
    uint64_t framesConcealed = 0;      ///< decoded with errors the decoder marked (left out)
    uint64_t continuityGaps = 0;       ///< transport packets missing (continuity-counter gaps, any stream)
    uint64_t framesDamaged = 0;        ///< video frames a gap fell in (shown concealed, or skipped)
    uint64_t klvPackets = 0, klvRejected = 0;   ///< rejected: bad checksum, undecodable, no pose
    uint64_t posesReceived = 0;
    uint64_t reconnects = 0;
    uint64_t packetsRecorded = 0;
    std::string recording;             ///< the file being recorded (or waiting for a key frame), or empty
    /// Wall time (UTC) now minus the UTC of the frame shown last (its KLV time stamp): the
    /// glass-to-drape latency. None without stamps, or stamps from another clock
    /// (plausibleLatency).
    std::optional<double> latencySeconds;
    int width = 0, height = 0;
    std::string lastError;             ///< why the last session ended, or empty
};

/// A frame due now, with its pose.
struct LiveFrame {
    std::shared_ptr<const VideoFrame> frame;   ///< frame->index: a serial number, increasing
    double streamTime = 0.0;                   ///< seconds on the stream's clock
    std::optional<SensorPose> pose;            ///< none before the first KLV pose
    std::optional<double> utc;                 ///< the frame's UTC from the KLV time stamps
    /// It, or a frame it refers to since the last key frame, lost data on the way: shown as the
    /// decoder concealed it.
    bool damaged = false;
};

class LiveVideo {
public:
    /// Starts receiving `url`; returns at once (the stream may not be there yet). Errors: an
    /// empty URL, a protocol this FFmpeg does not have (the message lists those it has), a
    /// recording path that cannot be written.
    static Result<std::unique_ptr<LiveVideo>> open(const std::string& url, LiveOptions options);
    ~LiveVideo();
    LiveVideo(const LiveVideo&) = delete;
    LiveVideo& operator=(const LiveVideo&) = delete;

    const std::string& url() const;
    /// Main thread, once a frame: the newest frame due at `wallSeconds` (UTC, seconds since
    /// 1970), which may be the one returned before; none before the first frame.
    std::optional<LiveFrame> due(double wallSeconds);
    LiveStats stats() const;
    /// Starts recording into `path` (from the next key frame, with the KLV of the second before
    /// it), or stops with an empty path; a recording under way is finished first. Errors: the
    /// file cannot be written.
    Result<void> record(const std::string& path);

    /// The input protocols of the FFmpeg this was built with ("udp", "tcp", "http", ...).
    static std::string inputProtocols();

private:
    LiveVideo() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// UTC now, seconds since 1970 (the wall clock live layers run on).
double wallClockSeconds();
/// Whether a frame's age (now minus its KLV time stamp) can be a latency: the sender's clock is
/// this one's, give or take a second (a recorded flight's stamps are from another day).
inline bool plausibleLatency(double seconds) { return seconds > -1.0 && seconds < 600.0; }

}  // namespace orbis::fmv
